// SPDX-License-Identifier: Apache-2.0
#include "Bake.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "Charts.h"
#include "Lod.h"
#include "MeshDistance.h"

namespace vdbmap::tiles3d {
namespace {

/// Shelf packing (tallest first) of the rectangles, no gaps (the margins are inside them);
/// returns the page size.
cv::Size pack(std::vector<Chart>& flats) {
    double area = 0;
    int widest = 1;
    for (const Chart& f : flats) {
        area += double(f.w) * f.h;
        widest = std::max(widest, f.w);
    }
    const int limit = std::max(widest, static_cast<int>(std::ceil(std::sqrt(area) * 1.02)));
    std::vector<std::size_t> order(flats.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return flats[a].h > flats[b].h; });
    int x = 0, y = 0, shelf = 0, width = 1;
    for (const std::size_t i : order) {
        Chart& f = flats[i];
        if (x > 0 && x + f.w > limit) {
            y += shelf;
            x = 0;
            shelf = 0;
        }
        f.x = x;
        f.y = y;
        x += f.w;
        shelf = std::max(shelf, f.h);
        width = std::max(width, x);
    }
    return {width, std::max(1, y + shelf)};
}

cv::Vec3b bilinear(const cv::Mat& page, const Eigen::Vector2d& uv) {
    const double x = std::clamp(uv.x() * page.cols - 0.5, 0.0, page.cols - 1.0);
    const double y = std::clamp(uv.y() * page.rows - 0.5, 0.0, page.rows - 1.0);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, page.cols - 1), y1 = std::min(y0 + 1, page.rows - 1);
    const double fx = x - x0, fy = y - y0;
    cv::Vec3b out;
    for (int ch = 0; ch < 3; ++ch) {
        const double v = (1 - fy) * ((1 - fx) * page.at<cv::Vec3b>(y0, x0)[ch] + fx * page.at<cv::Vec3b>(y0, x1)[ch]) +
                         fy * ((1 - fx) * page.at<cv::Vec3b>(y1, x0)[ch] + fx * page.at<cv::Vec3b>(y1, x1)[ch]);
        out[ch] = static_cast<uchar>(std::clamp(std::lround(v), 0L, 255L));
    }
    return out;
}

const cv::Vec3b kUntexturedBgr(153, 153, 153);  // the GLB's untextured material (0.6 grey)

}  // namespace

double texelSizeM(const TileMesh& mesh) {
    double area_m2 = 0, area_px = 0;
    for (std::size_t f = 0; f < mesh.faces(); ++f) {
        if (mesh.page[f] == kNoPage || mesh.uvs.empty()) continue;
        const cv::Mat& page = mesh.pages[mesh.page[f]];
        const auto& c = mesh.corners[f];
        const auto& t = mesh.uvs[f];
        area_m2 += 0.5 * static_cast<double>((c[1] - c[0]).cross(c[2] - c[0]).norm());
        const Eigen::Vector2d a(double(t[1].x() - t[0].x()) * page.cols, double(t[1].y() - t[0].y()) * page.rows);
        const Eigen::Vector2d b(double(t[2].x() - t[0].x()) * page.cols, double(t[2].y() - t[0].y()) * page.rows);
        area_px += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    }
    return area_px > 0 ? std::sqrt(area_m2 / area_px) : 0.0;
}

void bakeAtlas(TileMesh& target, const std::vector<const TileMesh*>& sources, double texel_m,
               int max_page_px, int gutter_px, BakeFigures* figures, const TriangleGrid* sources_grid) {
    const std::size_t n = target.faces();
    target.page.assign(n, kNoPage);
    target.label.assign(n, 255);
    target.confidence.assign(n, 0.0f);
    target.uvs.clear();
    target.pages.clear();

    // The sources' faces in W, and where each came from.
    std::vector<Triangle> triangles;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> origin;  // (source, face)
    bool textured = false;
    for (std::size_t s = 0; s < sources.size(); ++s) {
        const TileMesh& m = *sources[s];
        for (std::size_t f = 0; f < m.faces(); ++f) {
            if (!sources_grid) triangles.push_back({m.cornerW(f, 0), m.cornerW(f, 1), m.cornerW(f, 2)});
            origin.emplace_back(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(f));
            textured = textured || (m.page[f] != kNoPage && !m.uvs.empty());
        }
    }
    if (sources_grid && sources_grid->size() != origin.size()) {
        throw InvalidInput("bakeAtlas: the sources' grid has " + std::to_string(sources_grid->size()) +
                           " triangles, the sources " + std::to_string(origin.size()) + " faces");
    }
    if (n == 0 || origin.empty()) return;
    std::unique_ptr<TriangleGrid> own_grid;
    if (!sources_grid) own_grid = std::make_unique<TriangleGrid>(std::move(triangles));
    const TriangleGrid& grid = sources_grid ? *sources_grid : *own_grid;
    textured = textured && texel_m > 0;

    // The layout: charts of faces laid flat (Charts.h), each at texel_m metres per texel of
    // surface on average (its plane texel shrinks by sqrt(projected / true area)), texel_m
    // grown until the packed page fits.
    const int g = std::max(0, gutter_px);
    std::vector<Chart> charts;
    std::vector<std::vector<std::int32_t>> owners;
    std::vector<std::vector<std::uint8_t>> insides;  // per chart and texel: inside its face
    cv::Size size(0, 0);
    auto layout = [&]() {
        for (int attempt = 0;; ++attempt) {
            for (Chart& ch : charts) {
                const double c = ch.area_m2 > 0 ? std::clamp(ch.projected_m2 / ch.area_m2, 1.0 / 3.0, 1.0) : 1.0;
                ch.plane_texel_m = texel_m * std::sqrt(c);
                const Eigen::Vector2d extent = (ch.max_m - ch.min_m) / ch.plane_texel_m;
                // Even sizes (so even places): JPEG's 2 x 2 chroma blocks never straddle two
                // charts' rectangles.
                ch.w = (static_cast<int>(std::ceil(extent.x() + 2 * g)) + 1) & ~1;
                ch.h = (static_cast<int>(std::ceil(extent.y() + 2 * g)) + 1) & ~1;
                ch.w = std::max(ch.w, 2);
                ch.h = std::max(ch.h, 2);
            }
            size = pack(charts);
            const int side = std::max(size.width, size.height);
            if (side <= max_page_px || attempt > 60) break;
            texel_m *= std::max(1.02, 1.02 * double(side) / max_page_px);
        }
    };
    auto cornersPx = [&](const Chart& ch) {
        std::vector<std::array<Eigen::Vector2d, 3>> px(ch.faces.size());
        for (std::size_t j = 0; j < ch.faces.size(); ++j) {
            for (std::size_t k = 0; k < 3; ++k) {
                px[j][k] = (projectToChart(target.corners[ch.faces[j]][k].cast<double>(), ch.axis) - ch.min_m) /
                               ch.plane_texel_m +
                           Eigen::Vector2d::Constant(g);
            }
        }
        return px;
    };
    // Texels up to the margin plus a diagonal texel from a face show it.
    const double reach_px = g + 1.0;
    if (textured) {
        // Charts at most 256 texels (a quarter page) on a side at the first texel size.
        charts = buildCharts(target, texel_m * std::min(256, std::max(8, max_page_px / 4)));
        for (int round = 0;; ++round) {
            layout();
            owners.assign(charts.size(), {});
            insides.assign(charts.size(), {});
            std::vector<std::vector<std::uint32_t>> overlaps(charts.size());
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, charts.size(), 16), [&](const auto& range) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    overlaps[i] = rasterizeChart(cornersPx(charts[i]), charts[i].w, charts[i].h, reach_px, owners[i],
                                                 &insides[i]);
                }
            });
            if (round > 8 || std::all_of(overlaps.begin(), overlaps.end(), [](const auto& o) { return o.empty(); })) break;
            // A chart whose projection overlaps itself: the faces that overlap get charts of
            // their own (a chart of one face cannot overlap).
            std::vector<Chart> next;
            for (std::size_t i = 0; i < charts.size(); ++i) {
                if (overlaps[i].empty()) {
                    next.push_back(std::move(charts[i]));
                } else {
                    for (Chart& c : splitChart(target, charts[i], overlaps[i])) next.push_back(std::move(c));
                }
            }
            charts = std::move(next);
        }
        target.pages.emplace_back(size, CV_8UC3, cv::Scalar(0, 0, 0));
        target.uvs.resize(n);
    }
    cv::Mat* page = textured ? &target.pages.front() : nullptr;
    std::vector<double> chart_distance;  // per chart: the largest texel distance

    // A face's class and confidence: the most frequent class of its votes, their mean confidence.
    auto decide = [&](std::size_t f, std::vector<std::pair<std::uint8_t, float>>& votes) {
        if (votes.empty()) return;
        std::sort(votes.begin(), votes.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        std::size_t best_begin = 0, best_count = 0;
        for (std::size_t i = 0; i < votes.size();) {
            std::size_t j = i;
            while (j < votes.size() && votes[j].first == votes[i].first) ++j;
            if (j - i > best_count) {
                best_count = j - i;
                best_begin = i;
            }
            i = j;
        }
        double sum = 0;
        for (std::size_t i = best_begin; i < best_begin + best_count; ++i) sum += votes[i].second;
        target.label[f] = votes[best_begin].first;
        target.confidence[f] = static_cast<float>(sum / double(best_count));
    };
    // Nearest source point of a W point (a local search in the grid's cells, the previous
    // query's triangle tried first): its colour, class and confidence.
    auto sample = [&](const Eigen::Vector3d& p, int& hint, cv::Vec3b* colour, std::uint8_t* label, float* conf,
                      double* distance_m = nullptr) {
        Eigen::Vector3d q;
        const int i = grid.nearest(p, q, hint);
        if (i < 0) return false;
        hint = i;
        if (distance_m) *distance_m = std::max(*distance_m, (p - q).norm());
        const auto [s, sf] = origin[static_cast<std::size_t>(i)];
        const TileMesh& m = *sources[s];
        if (label) *label = m.label[sf];
        if (conf) *conf = m.confidence[sf];
        if (colour) {
            if (m.page[sf] == kNoPage || m.uvs.empty()) {
                *colour = kUntexturedBgr;
            } else {
                const Eigen::Vector3d w = barycentric(q, grid.triangle(static_cast<std::size_t>(i)));
                Eigen::Vector2d uv = Eigen::Vector2d::Zero();
                for (int k = 0; k < 3; ++k) uv += w[k] * m.uvs[sf][static_cast<std::size_t>(k)].cast<double>();
                *colour = bilinear(m.pages[m.page[sf]], uv);
            }
        }
        return true;
    };
    auto centroidVote = [&](std::size_t f, int& hint, std::vector<std::pair<std::uint8_t, float>>& votes) {
        std::uint8_t label = 255;
        float conf = 0;
        const Eigen::Vector3d centre = (target.cornerW(f, 0) + target.cornerW(f, 1) + target.cornerW(f, 2)) / 3.0;
        if (sample(centre, hint, nullptr, &label, &conf)) votes.emplace_back(label, conf);
    };

    if (!page) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const auto& range) {
            std::vector<std::pair<std::uint8_t, float>> votes;
            int hint = -1;
            for (std::size_t f = range.begin(); f != range.end(); ++f) {
                votes.clear();
                centroidVote(f, hint, votes);
                decide(f, votes);
            }
        });
    } else {
        // Every texel of a chart: the nearest point of the face it shows, then the sources'
        // colour there; texel centres inside a face vote for its class. Parallel over charts,
        // each writing its own rectangle and faces, in a fixed order within a chart.
        const double inv_w = 1.0 / page->cols, inv_h = 1.0 / page->rows;
        chart_distance.assign(charts.size(), 0.0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, charts.size(), 1), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                const Chart& ch = charts[i];
                const auto px = cornersPx(ch);
                const std::vector<std::int32_t>& owner = owners[i];
                std::vector<std::vector<std::pair<std::uint8_t, float>>> votes(ch.faces.size());
                for (std::size_t j = 0; j < ch.faces.size(); ++j) {
                    const std::size_t f = ch.faces[j];
                    target.page[f] = 0;
                    for (std::size_t k = 0; k < 3; ++k) {
                        target.uvs[f][k] = Eigen::Vector2f(static_cast<float>((ch.x + px[j][k].x()) * inv_w),
                                                           static_cast<float>((ch.y + px[j][k].y()) * inv_h));
                    }
                }
                // Texels inside a face first (each the sources' colour at its point), then the
                // margin texels: the colour of the inside texel under their point on the face
                // (a dilation), or the sources' where that texel is not inside a face.
                int hint = -1;
                std::vector<char> inner(owner.size(), 0);
                for (int pass = 0; pass < 2; ++pass) {
                    for (int r = 0; r < ch.h; ++r) {
                        for (int c = 0; c < ch.w; ++c) {
                            const std::size_t t = std::size_t(r) * std::size_t(ch.w) + std::size_t(c);
                            const std::int32_t j = owner[t];
                            if (j < 0 || (insides[i][t] != 0) != (pass == 0)) continue;
                            const auto& tri = px[static_cast<std::size_t>(j)];
                            const Nearest2 on = nearestOnTriangle2(Eigen::Vector2d(c + 0.5, r + 0.5), tri);
                            const bool inside = on.distance2 == 0;
                            if (!inside) {
                                const Eigen::Vector2d at = on.weights[0] * tri[0] + on.weights[1] * tri[1] + on.weights[2] * tri[2];
                                const int ac = std::clamp(static_cast<int>(std::floor(at.x())), 0, ch.w - 1);
                                const int ar = std::clamp(static_cast<int>(std::floor(at.y())), 0, ch.h - 1);
                                if (inner[std::size_t(ar) * std::size_t(ch.w) + std::size_t(ac)]) {
                                    page->at<cv::Vec3b>(ch.y + r, ch.x + c) = page->at<cv::Vec3b>(ch.y + ar, ch.x + ac);
                                    continue;
                                }
                            }
                            const std::size_t f = ch.faces[static_cast<std::size_t>(j)];
                            Eigen::Vector3d p = Eigen::Vector3d::Zero();
                            for (int k = 0; k < 3; ++k) p += on.weights[k] * target.cornerW(f, k);
                            cv::Vec3b colour = kUntexturedBgr;
                            std::uint8_t label = 255;
                            float conf = 0;
                            if (sample(p, hint, &colour, &label, &conf, &chart_distance[i]) && inside) {
                                votes[static_cast<std::size_t>(j)].emplace_back(label, conf);
                            }
                            page->at<cv::Vec3b>(ch.y + r, ch.x + c) = colour;
                            inner[t] = inside ? 1 : 0;
                        }
                    }
                }
                for (std::size_t j = 0; j < ch.faces.size(); ++j) {
                    if (votes[j].empty()) centroidVote(ch.faces[j], hint, votes[j]);
                    decide(ch.faces[j], votes[j]);
                }
            }
        });
    }
    if (figures) {
        figures->texel_m = textured ? texel_m : 0.0;
        figures->page_width = size.width;
        figures->page_height = size.height;
        std::size_t texels = 0;
        for (const Chart& ch : charts) texels += std::size_t(ch.w) * std::size_t(ch.h);
        figures->charts = charts.size();
        figures->max_texel_distance_m =
            chart_distance.empty() ? 0.0 : *std::max_element(chart_distance.begin(), chart_distance.end());
        figures->texels = texels;
    }
}

}  // namespace vdbmap::tiles3d
