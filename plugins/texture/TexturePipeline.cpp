// SPDX-License-Identifier: Apache-2.0
#include "TexturePipeline.h"
#include "SmoothFill.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>

#include "FaceStats.h"
#include "Patches.h"
#include "TextureAtlas.h"
#include "ViewSelection.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/mrf/PottsMrf.h"

namespace vdbmap::texture {

namespace {

/// The image centre (u, v) of the paper's vignetting radius: the middle of the pixel grid.
double imageCentreU(const CameraIntrinsics& in) { return (in.width - 1) / 2.0; }
double imageCentreV(const CameraIntrinsics& in) { return (in.height - 1) / 2.0; }

/// Loads view v, converts `crop` of it (default: the whole image) to float and applies the
/// vignetting correction of its camera there, then divides by the view's exposure gain.
cv::Mat loadCorrected(const ImageLoader& load, const std::vector<View>& views, std::size_t v,
                      const std::vector<VignettingParams>* vignetting, cv::Rect crop = {},
                      double gain = 1.0) {
    const cv::Mat image_u8 = load(v);
    const View& view = views[v];
    if (image_u8.cols != view.intrinsics.width || image_u8.rows != view.intrinsics.height) {
        throw InvalidInput("texture: image of view " + std::to_string(v) + " (frame " +
                           std::to_string(view.frame) + ", camera " + std::to_string(view.camera) +
                           ") is " + std::to_string(image_u8.cols) + "x" +
                           std::to_string(image_u8.rows) + " but the camera is " +
                           std::to_string(view.intrinsics.width) + "x" +
                           std::to_string(view.intrinsics.height));
    }
    const cv::Rect whole(0, 0, image_u8.cols, image_u8.rows);
    crop = crop.empty() ? whole : (crop & whole);
    cv::Mat image = toFloatBgr(image_u8(crop));
    if (vignetting && view.camera < vignetting->size()) {
        correctVignetting(image, (*vignetting)[view.camera], imageCentreU(view.intrinsics),
                          imageCentreV(view.intrinsics), crop.tl());
    }
    if (gain != 1.0) image *= 1.0 / gain;
    return image;
}

/// The statistics of view v's observations `obs_indices`, read from the part of the image they
/// cover (FaceStats.h: observedBounds).
void viewStats(const ImageLoader& load, const std::vector<View>& views, std::size_t v,
               const std::vector<VignettingParams>* vignetting, const Visibility& vis,
               const std::vector<std::uint64_t>& obs_indices, bool with_quality,
               std::vector<ObservationStats>& stats) {
    const cv::Size image_size(views[v].intrinsics.width, views[v].intrinsics.height);
    const cv::Rect crop = observedBounds(vis, obs_indices, image_size, kStatsMarginPx);
    if (crop.empty()) return;
    const cv::Mat image = loadCorrected(load, views, v, vignetting, crop);
    computeObservationStats(image, crop.tl(), image_size, vis, obs_indices, with_quality, stats);
}

/// Part of a view's image: `pixels` (CV_32FC3) is the crop at `origin` of an image of `size`.
struct ImageCrop {
    cv::Mat pixels;
    cv::Point origin;
    cv::Size size;
};

/// Bilinear colour at a continuous pixel position (docs/DATA.md convention), clamped to the image.
Vec3f sampleBilinear(const ImageCrop& image, const Eigen::Vector2f& p) {
    const int width = image.size.width, height = image.size.height;
    const float x = std::clamp(p.x(), 0.0f, float(width - 1));
    const float y = std::clamp(p.y(), 0.0f, float(height - 1));
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const float tx = x - x0, ty = y - y0;
    auto at = [&](int yy, int xx) {
        const cv::Vec3f& c = image.pixels.at<cv::Vec3f>(yy - image.origin.y, xx - image.origin.x);
        return Vec3f(c[0], c[1], c[2]);
    };
    return (1 - ty) * ((1 - tx) * at(y0, x0) + tx * at(y0, x1)) +
           ty * ((1 - tx) * at(y1, x0) + tx * at(y1, x1));
}

/// f_v of the seam-levelling equation: the mean colour along the seam edge from `from` to the
/// edge midpoint (Lempitsky & Ivanov sample along the edge next to the vertex).
Vec3f sampleSeamEnd(const ImageCrop& image, const Eigen::Vector2f& from,
                    const Eigen::Vector2f& to) {
    constexpr int kSamples = 5;
    Vec3f sum = Vec3f::Zero();
    for (int k = 0; k < kSamples; ++k) {
        const float t = 0.5f * static_cast<float>(k) / kSamples;
        sum += sampleBilinear(image, from + t * (to - from));
    }
    return sum / static_cast<float>(kSamples);
}

/// The pixels a rectangle reads with its coordinates clamped to the image (never empty).
cv::Rect clampedRect(int x0, int y0, int x1, int y1, cv::Size size) {
    const int cx0 = std::clamp(x0, 0, size.width - 1), cy0 = std::clamp(y0, 0, size.height - 1);
    const int cx1 = std::clamp(x1, 0, size.width - 1), cy1 = std::clamp(y1, 0, size.height - 1);
    return {cx0, cy0, cx1 - cx0 + 1, cy1 - cy0 + 1};
}

/// Pixel of a continuous coordinate, clamped to [-1, limit] first (no int overflow).
int pixelFloor(float value, int limit) {
    return static_cast<int>(std::floor(std::clamp(value, -1.0f, static_cast<float>(limit))));
}

int cornerOf(const std::array<std::uint32_t, 3>& face, std::uint32_t vertex) {
    for (int k = 0; k < 3; ++k) {
        if (face[k] == vertex) return k;
    }
    return 0;
}

class StepClock {
public:
    explicit StepClock(TextureStats& stats) : stats_(stats) {}
    void done(const std::string& step) {
        stats_.timings_s.emplace_back(step, timer_.elapsedSeconds());
        stats_.peak_memory_bytes.emplace_back(step, peakMemoryBytes());
        timer_.reset();
    }

private:
    TextureStats& stats_;
    Timer timer_;
};

void checkInputs(const MeshArrays& mesh, const std::vector<View>& views, const Visibility& vis,
                 const TextureOptions& options) {
    if (vis.numFaces() != mesh.faces.size()) {
        throw InvalidInput("texture: visibility covers " + std::to_string(vis.numFaces()) +
                           " faces but the mesh has " + std::to_string(mesh.faces.size()));
    }
    for (const auto& face : mesh.faces) {
        for (std::uint32_t v : face) {
            if (v >= mesh.vertices_W.size()) {
                throw InvalidInput("texture: face refers to vertex " + std::to_string(v) + " of " +
                                   std::to_string(mesh.vertices_W.size()));
            }
        }
    }
    for (const auto& obs : vis.obs) {
        if (obs.view >= views.size()) {
            throw InvalidInput("texture: visibility refers to view " + std::to_string(obs.view) +
                               " of " + std::to_string(views.size()));
        }
    }
    if (options.lambda < 0) {
        throw InvalidInput("texture: lambda must be >= 0, got " + std::to_string(options.lambda));
    }
}

/// Beyond the paper: estimates (a, b, c) per camera from the uncorrected observations.
std::vector<VignettingEstimate> estimateFromImages(
    const std::vector<View>& views, const Visibility& vis,
    const std::vector<std::vector<std::uint64_t>>& per_view, const ImageLoader& load, bool quiet) {
    std::vector<ObservationStats> raw(vis.obs.size());
    Progress progress("texture: vignetting samples", views.size(), quiet);
    tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t v) {
        if (!per_view[v].empty()) {
            viewStats(load, views, v, nullptr, vis, per_view[v], false, raw);
        }
        progress.tick();
    });
    progress.finish();
    std::vector<VignettingSample> samples;
    std::size_t num_cameras = 0;
    std::vector<std::uint32_t> view_camera(views.size());
    for (std::size_t v = 0; v < views.size(); ++v) {
        view_camera[v] = static_cast<std::uint32_t>(views[v].camera);
        num_cameras = std::max(num_cameras, views[v].camera + 1);
    }
    for (std::size_t f = 0; f < vis.numFaces(); ++f) {
        if (vis.count(f) < 2) continue;
        for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
            const FaceObservation& obs = vis.obs[i];
            const float luminance = raw[i].mean_bgr.mean();
            // Dark and saturated faces carry no vignetting signal.
            if (luminance < 8.0f || luminance > 250.0f) continue;
            const Eigen::Vector2f c = (obs.pixels[0] + obs.pixels[1] + obs.pixels[2]) / 3.0f;
            const auto& in = views[obs.view].intrinsics;
            samples.push_back({static_cast<std::uint32_t>(f), obs.view, luminance,
                               static_cast<float>(vignettingRadius(c.x(), c.y(), imageCentreU(in),
                                                                   imageCentreV(in)))});
        }
    }
    return estimateVignetting(samples, view_camera, num_cameras);
}

/// Colours of the faces no view saw. Fill "smooth" (smooth_fill): the harmonic fill of the
/// textured faces' mean colours (harmonicFill), weighted by the crease angle (creaseWeights). Fill "neighbour": the mean colour (in its chosen view) of
/// the nearest textured face through the face adjacency (breadth-first), quantised to 16 levels
/// per channel so that a palette of at most 4096 cells holds them; faces with no textured face
/// in their component, and every face under fill "grey", get fill_bgr. Returns the palette and
/// the cell of each untextured face.
std::vector<Vec3f> fillPalette(const MeshArrays& mesh, const std::vector<std::uint32_t>& face_view,
                               const std::vector<Vec3f>& face_color,
                               const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                               const TextureOptions& options, std::vector<std::uint32_t>& cell) {
    const std::size_t n = face_view.size();
    cell.assign(n, 0);
    const Vec3f grey(options.fill_bgr[0], options.fill_bgr[1], options.fill_bgr[2]);
    std::vector<Vec3f> palette;
    std::vector<std::int32_t> cell_of_key(4097, -1);  // 4096: fill_bgr exactly
    auto cellOf = [&](const Vec3f& c) {
        int key = 0;
        Vec3f q;
        for (int k = 0; k < 3; ++k) {
            const int level = std::clamp(static_cast<int>(std::lround(c[k] / 17.0f)), 0, 15);
            key = key * 16 + level;
            q[k] = static_cast<float>(level * 17);
        }
        if (cell_of_key[key] < 0) {
            cell_of_key[key] = static_cast<std::int32_t>(palette.size());
            palette.push_back(q);
        }
        return static_cast<std::uint32_t>(cell_of_key[key]);
    };
    std::vector<Vec3f> color(face_color);
    std::vector<char> known(n, 0);
    std::deque<std::uint32_t> frontier;
    if (options.fill_from_neighbours && options.smooth_fill) {
        // Harmonic fill: colours diffused from the textured border (SmoothFill.h).
        for (std::uint32_t f = 0; f < n; ++f) known[f] = face_view[f] != kNoLabel;
        std::vector<char> filled;
        // Weighted by the crease angle, so that colours do not run across object edges.
        const std::vector<float> weights = creaseWeights(mesh.vertices_W, mesh.faces, adjacency);
        color = harmonicFill(known, face_color, adjacency, filled, &weights);
        for (std::uint32_t f = 0; f < n; ++f) known[f] = known[f] || filled[f];
    } else if (options.fill_from_neighbours) {
        for (std::uint32_t f = 0; f < n; ++f) {
            if (face_view[f] != kNoLabel) {
                known[f] = 1;
                frontier.push_back(f);
            }
        }
        std::vector<std::uint64_t> offsets(n + 1, 0);
        for (const auto& [a, b] : adjacency) {
            ++offsets[a + 1];
            ++offsets[b + 1];
        }
        for (std::size_t f = 0; f < n; ++f) offsets[f + 1] += offsets[f];
        std::vector<std::uint32_t> neighbours(offsets.back());
        std::vector<std::uint64_t> fill_at(offsets.begin(), offsets.end() - 1);
        for (const auto& [a, b] : adjacency) {
            neighbours[fill_at[a]++] = b;
            neighbours[fill_at[b]++] = a;
        }
        while (!frontier.empty()) {
            const std::uint32_t f = frontier.front();
            frontier.pop_front();
            for (std::uint64_t k = offsets[f]; k < offsets[f + 1]; ++k) {
                const std::uint32_t g = neighbours[k];
                if (known[g]) continue;
                known[g] = 1;
                color[g] = color[f];
                frontier.push_back(g);
            }
        }
    }
    for (std::uint32_t f = 0; f < n; ++f) {
        if (face_view[f] != kNoLabel) continue;
        if (known[f]) {
            cell[f] = cellOf(color[f]);
            continue;
        }
        if (cell_of_key[4096] < 0) {
            cell_of_key[4096] = static_cast<std::int32_t>(palette.size());
            palette.push_back(grey);
        }
        cell[f] = static_cast<std::uint32_t>(cell_of_key[4096]);
    }
    return palette;
}

// Phase: the vignetting models used (paper Sec. 5.2.1): given per camera, or estimated from
// the overlaps. Null when vignetting is off.
std::vector<VignettingParams> vignettingModels(const std::vector<View>& views,
                                               const Visibility& vis,
                                               const std::vector<std::vector<std::uint64_t>>& per_view,
                                               const ImageLoader& load,
                                               const TextureOptions& options, TextureStats& stats,
                                               StepClock& clock) {
    std::vector<VignettingParams> vignetting = options.vignetting_params;
    if (options.vignetting && options.estimate_vignetting) {
        stats.vignetting_estimates = estimateFromImages(views, vis, per_view, load, options.quiet);
        vignetting.clear();
        for (const auto& e : stats.vignetting_estimates) vignetting.push_back(e.params);
        clock.done("vignetting_estimate");
    }
    if (options.vignetting) stats.vignetting_used = vignetting;
    return vignetting;
}

// Phase (pass 1): E_Q (paper Eq. E_Q) and the mean colour of every observation, one image per
// task.
std::vector<ObservationStats> observationPass(const std::vector<View>& views,
                                              const Visibility& vis,
                                              const std::vector<std::vector<std::uint64_t>>& per_view,
                                              const ImageLoader& load,
                                              const std::vector<VignettingParams>* vignetting,
                                              bool quiet) {
    std::vector<ObservationStats> obs_stats(vis.obs.size());
    Progress progress("texture: data term", views.size(), quiet);
    tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t v) {
        if (!per_view[v].empty()) {
            viewStats(load, views, v, vignetting, vis, per_view[v], true, obs_stats);
        }
        progress.tick();
    });
    return obs_stats;
}

// Phase: view selection (paper Sec. 5.1), the chosen view per face.
std::vector<std::uint32_t> chooseViews(const Visibility& vis,
                                       const std::vector<ObservationStats>& obs_stats,
                                       const std::vector<char>& keep,
                                       const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                       std::size_t num_views, const TextureOptions& options,
                                       TextureStats& stats) {
    const MrfProblem problem = buildViewSelectionProblem(
        vis, obs_stats, keep, adjacency, num_views, options.lambda, options.max_candidates);
    const MrfSolution solution = selectViews(problem, options.use_mrf);
    stats.energy_initial = solution.initial_energy;
    stats.energy_final = solution.final_energy;
    stats.mrf_sweeps = solution.sweeps;
    std::ostringstream msg;
    msg << "texture: view selection energy " << solution.initial_energy << " -> "
        << solution.final_energy << (options.use_mrf ? " (alpha-expansion)" : " (best view)");
    logInfo(msg.str());
    return solution.labels;
}

// What the layout phase hands to the atlas passes.
struct Layout {
    std::vector<std::uint32_t> face_patch;
    std::vector<std::array<Eigen::Vector2f, 3>> face_pixels;
    std::vector<std::uint32_t> face_fill_cell;
    std::vector<Vec3f> palette;
    AtlasLayout atlas;
    std::vector<SeamEdge> seams;
};

// Phase: patches, the chosen view's projection of each face, the fill of untextured faces,
// the atlas layout (empty pages allocated in `result`) and the seam edges.
Layout layoutPhase(const MeshArrays& mesh, const Visibility& vis,
                   const std::vector<ObservationStats>& obs_stats,
                   const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                   const TextureOptions& options, TextureResult& result) {
    TextureStats& stats = result.stats;
    Layout out;
    const std::vector<Patch> patches = buildPatches(result.face_view, adjacency, &out.face_patch);
    out.face_pixels.resize(mesh.faces.size());
    std::vector<Vec3f> face_color(mesh.faces.size(), Vec3f::Zero());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const std::uint32_t view = result.face_view[f];
        if (view == kNoLabel) {
            ++stats.faces_untextured;
            continue;
        }
        const FaceObservation* it =
            std::lower_bound(vis.begin(f), vis.end(f), view,
                             [](const FaceObservation& o, std::uint32_t v) { return o.view < v; });
        out.face_pixels[f] = it->pixels;
        face_color[f] = obs_stats[static_cast<std::size_t>(it - vis.obs.data())].mean_bgr;
    }
    out.palette = fillPalette(mesh, result.face_view, face_color, adjacency, options, out.face_fill_cell);
    out.atlas = layoutAtlas(patches, out.face_pixels, mesh.faces.size(), options.padding_px,
                            options.atlas_max_size_px, static_cast<int>(out.palette.size()));
    stats.patches = patches.size();
    stats.charts = out.atlas.charts.size();
    stats.pages = out.atlas.pages.size();
    result.pages.reserve(out.atlas.pages.size());
    for (const RectSize& s : out.atlas.pages) {
        result.pages.emplace_back(s.height, s.width, CV_8UC3, cv::Scalar(0, 0, 0));
    }
    if (options.global_adjustment) out.seams = findSeamEdges(mesh, out.face_patch, adjacency);
    stats.seam_edges = out.seams.size();
    return out;
}

/// The part of view v's image the atlas pass reads: its charts' source rectangles and the
/// seam samples of its faces (why: as FaceStats.h observedBounds).
ImageCrop atlasCrop(const ImageLoader& load, const std::vector<View>& views, std::size_t v,
                    const std::vector<VignettingParams>* vignetting, double gain,
                    const MeshArrays& mesh, const Layout& layout,
                    const std::vector<std::uint32_t>& charts,
                    const std::vector<std::pair<std::uint32_t, bool>>& seams) {
    const cv::Size size(views[v].intrinsics.width, views[v].intrinsics.height);
    cv::Rect crop;
    auto add = [&](const cv::Rect& r) { crop = crop.empty() ? r : (crop | r); };
    for (std::uint32_t c : charts) {
        const Chart& chart = layout.atlas.charts[c];
        add(clampedRect(chart.x0, chart.y0, chart.x0 + chart.size.width - 1,
                        chart.y0 + chart.size.height - 1, size));
    }
    for (const auto& [k, side_a] : seams) {
        const SeamEdge& s = layout.seams[k];
        const std::uint32_t face = side_a ? s.face_a : s.face_b;
        const auto& px = layout.face_pixels[face];
        for (const std::uint32_t vertex : {s.v0, s.v1}) {
            const Eigen::Vector2f& p = px[cornerOf(mesh.faces[face], vertex)];
            const int x = pixelFloor(p.x(), size.width), y = pixelFloor(p.y(), size.height);
            add(clampedRect(x, y, x + 1, y + 1, size));  // bilinear: the pixel and the next
        }
    }
    ImageCrop image;
    image.pixels = loadCorrected(load, views, v, vignetting, crop, gain);
    image.origin = crop.tl();
    image.size = size;
    return image;
}

// Phase (pass 2): cut the charts from the (corrected) chosen views and sample the seams.
std::vector<SeamSamples> atlasPass(const MeshArrays& mesh, const std::vector<View>& views,
                                   const ImageLoader& load,
                                   const std::vector<VignettingParams>* vignetting,
                                   const std::vector<double>& gains, const Layout& layout,
                                   bool quiet, TextureResult& result) {
    std::vector<std::vector<std::uint32_t>> charts_of_view(views.size());
    for (std::uint32_t c = 0; c < layout.atlas.charts.size(); ++c) {
        charts_of_view[layout.atlas.charts[c].view].push_back(c);
    }
    const std::vector<SeamEdge>& seams = layout.seams;
    std::vector<std::vector<std::pair<std::uint32_t, bool>>> seams_of_view(views.size());
    for (std::uint32_t k = 0; k < seams.size(); ++k) {
        seams_of_view[result.face_view[seams[k].face_a]].emplace_back(k, true);
        seams_of_view[result.face_view[seams[k].face_b]].emplace_back(k, false);
    }
    std::vector<SeamSamples> samples(seams.size());
    Progress progress("texture: atlas", views.size(), quiet);
    tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t v) {
        if (!charts_of_view[v].empty() || !seams_of_view[v].empty()) {
            const double gain = v < gains.size() ? gains[v] : 1.0;
            const ImageCrop image = atlasCrop(load, views, v, vignetting, gain, mesh, layout,
                                              charts_of_view[v], seams_of_view[v]);
            for (std::uint32_t c : charts_of_view[v]) {
                const Chart& chart = layout.atlas.charts[c];
                cutChart(image.pixels, chart, result.pages[chart.place.page], image.origin,
                         image.size);
            }
            for (const auto& [k, side_a] : seams_of_view[v]) {
                const SeamEdge& s = seams[k];
                const std::uint32_t face = side_a ? s.face_a : s.face_b;
                const auto& px = layout.face_pixels[face];
                const Eigen::Vector2f p0 = px[cornerOf(mesh.faces[face], s.v0)];
                const Eigen::Vector2f p1 = px[cornerOf(mesh.faces[face], s.v1)];
                Vec3f& at_v0 = side_a ? samples[k].a_v0 : samples[k].b_v0;
                Vec3f& at_v1 = side_a ? samples[k].a_v1 : samples[k].b_v1;
                at_v0 = sampleSeamEnd(image, p0, p1);
                at_v1 = sampleSeamEnd(image, p1, p0);
            }
        }
        progress.tick();
    });
    return samples;
}

// Phase: global colour adjustment (paper Eq. seam_levelling) applied to the charts.
void levelSeams(const MeshArrays& mesh, const Layout& layout,
                const std::vector<SeamSamples>& samples, const TextureOptions& options,
                TextureResult& result) {
    SeamLevelingResult leveling =
        solveSeamLeveling(mesh, layout.face_patch, layout.seams, samples, options.leveling);
    tbb::parallel_for(std::size_t{0}, layout.atlas.charts.size(), [&](std::size_t c) {
        const Chart& chart = layout.atlas.charts[c];
        applyChartCorrection(chart, layout.face_pixels, leveling.corner_correction,
                             result.pages[chart.place.page], leveling.log_gain);
    });
    leveling.corner_correction.clear();
    leveling.corner_correction.shrink_to_fit();
    result.stats.leveling_summary = std::move(leveling);
}

// Phase: the palette block of the untextured faces' colours.
void paintFillCells(const Layout& layout, TextureResult& result) {
    if (!layout.atlas.has_fill_block) return;
    for (std::size_t cell = 0; cell < layout.palette.size(); ++cell) {
        const RectPlacement origin = fillCellOrigin(layout.atlas, static_cast<int>(cell));
        const Vec3f& c = layout.palette[cell];
        result.pages[origin.page](cv::Rect(origin.x, origin.y, kFillCellPx, kFillCellPx))
            .setTo(cv::Scalar(c[0], c[1], c[2]));
    }
}

}  // namespace

TextureResult textureMesh(const MeshArrays& mesh, const std::vector<View>& views,
                          const Visibility& vis,
                          const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                          const ImageLoader& load, const TextureOptions& options) {
    checkInputs(mesh, views, vis, options);
    TextureResult result;
    TextureStats& stats = result.stats;
    stats.faces = mesh.faces.size();
    stats.views = views.size();
    stats.observations = vis.obs.size();
    StepClock clock(stats);
    const auto per_view = observationsPerView(vis, views.size());

    const std::vector<VignettingParams> vignetting =
        vignettingModels(views, vis, per_view, load, options, stats, clock);
    const std::vector<VignettingParams>* vignetting_used =
        options.vignetting ? &vignetting : nullptr;

    std::vector<ObservationStats> obs_stats =
        observationPass(views, vis, per_view, load, vignetting_used, options.quiet);
    clock.done("data_term");

    // Exposure before view selection: E_Q and the mean colours become those of the corrected
    // images (both are linear in the image), so the MRF and photo-consistency compare them.
    if (options.exposure_gains) {
        ExposureResult exposure =
            estimateExposureGains(vis, obs_stats, views.size(), options.exposure);
        applyExposureGains(vis, exposure.gain, obs_stats);
        stats.exposure_gains = std::move(exposure.gain);
        stats.exposure_faces = exposure.faces_used;
        stats.exposure_views_without_overlap = exposure.views_without_overlap.size();
        if (!exposure.views_without_overlap.empty()) {
            logWarn("texture: " + std::to_string(exposure.views_without_overlap.size()) +
                    " view(s) share no usable face with another view (first: view " +
                    std::to_string(exposure.views_without_overlap.front()) +
                    "); their exposure gain stays 1");
        }
        clock.done("exposure_gains");
    }

    std::vector<char> keep(vis.obs.size(), 1);
    if (options.photo_consistency) {
        stats.photo_rejected = applyPhotoConsistency(vis, obs_stats, options.photo, keep);
        clock.done("photo_consistency");
    }

    result.face_view = chooseViews(vis, obs_stats, keep, adjacency, views.size(), options, stats);
    clock.done("mrf");

    const Layout layout = layoutPhase(mesh, vis, obs_stats, adjacency, options, result);
    clock.done("patches_layout");

    const std::vector<SeamSamples> samples =
        atlasPass(mesh, views, load, vignetting_used, stats.exposure_gains, layout,
                  options.quiet, result);
    clock.done("atlas_cut");

    if (options.global_adjustment) {
        levelSeams(mesh, layout, samples, options, result);
        clock.done("global_adjustment");
    }

    paintFillCells(layout, result);
    faceUvs(layout.atlas, layout.face_pixels, result.face_uvs, result.face_page,
            layout.face_fill_cell);
    clock.done("uvs");
    return result;
}

}  // namespace vdbmap::texture
