// SPDX-License-Identifier: Apache-2.0
#include "TextureAtlas.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "Raster.h"
#include "vdbmap/Error.h"
#include "vdbmap/mrf/PottsMrf.h"

namespace vdbmap::texture {

namespace {

Chart makeChart(std::uint32_t patch, std::uint32_t view, std::vector<std::uint32_t> faces,
                const std::vector<std::array<Eigen::Vector2f, 3>>& face_pixels, int padding_px) {
    float min_x = std::numeric_limits<float>::infinity(), min_y = min_x;
    float max_x = -min_x, max_y = -min_x;
    for (std::uint32_t f : faces) {
        for (const auto& p : face_pixels[f]) {
            min_x = std::min(min_x, p.x());
            min_y = std::min(min_y, p.y());
            max_x = std::max(max_x, p.x());
            max_y = std::max(max_y, p.y());
        }
    }
    Chart chart;
    chart.patch = patch;
    chart.view = view;
    chart.faces = std::move(faces);
    chart.x0 = static_cast<int>(std::floor(min_x)) - padding_px;
    chart.y0 = static_cast<int>(std::floor(min_y)) - padding_px;
    chart.size.width = static_cast<int>(std::ceil(max_x)) + padding_px - chart.x0 + 1;
    chart.size.height = static_cast<int>(std::ceil(max_y)) + padding_px - chart.y0 + 1;
    return chart;
}

}  // namespace

AtlasLayout layoutAtlas(const std::vector<Patch>& patches,
                        const std::vector<std::array<Eigen::Vector2f, 3>>& face_pixels,
                        std::size_t num_faces, int padding_px, int max_size_px, int fill_cells) {
    if (padding_px < 0) {
        throw InvalidInput("layoutAtlas: padding_px must be >= 0, got " +
                           std::to_string(padding_px));
    }
    AtlasLayout layout;
    layout.face_chart.assign(num_faces, kNoLabel);
    for (std::uint32_t p = 0; p < patches.size(); ++p) {
        Chart chart = makeChart(p, patches[p].view, patches[p].faces, face_pixels, padding_px);
        if (chart.size.width <= max_size_px && chart.size.height <= max_size_px) {
            layout.charts.push_back(std::move(chart));
            continue;
        }
        for (std::uint32_t f : patches[p].faces) {
            layout.charts.push_back(makeChart(p, patches[p].view, {f}, face_pixels, padding_px));
        }
    }
    std::vector<RectSize> sizes;
    sizes.reserve(layout.charts.size() + 1);
    for (std::uint32_t c = 0; c < layout.charts.size(); ++c) {
        sizes.push_back(layout.charts[c].size);
        for (std::uint32_t f : layout.charts[c].faces) layout.face_chart[f] = c;
    }
    layout.has_fill_block = std::find(layout.face_chart.begin(), layout.face_chart.end(),
                                      kNoLabel) != layout.face_chart.end();
    if (layout.has_fill_block) {
        layout.fill_cells = std::max(fill_cells, 1);
        layout.fill_size = {std::min(layout.fill_cells, kFillColumns) * kFillCellPx,
                            ((layout.fill_cells + kFillColumns - 1) / kFillColumns) * kFillCellPx};
        sizes.push_back(layout.fill_size);
    }
    PackResult packed = packRects(sizes, max_size_px);
    for (std::size_t c = 0; c < layout.charts.size(); ++c)
        layout.charts[c].place = packed.placements[c];
    if (layout.has_fill_block) layout.fill_place = packed.placements.back();
    layout.pages = std::move(packed.pages);
    return layout;
}

void cutChart(const cv::Mat& image_f32, const Chart& chart, cv::Mat& page, cv::Point origin,
              cv::Size image_size) {
    if (image_size.empty()) image_size = image_f32.size();
    for (int j = 0; j < chart.size.height; ++j) {
        const int sy = std::clamp(chart.y0 + j, 0, image_size.height - 1) - origin.y;
        const auto* src = image_f32.ptr<cv::Vec3f>(sy);
        auto* dst = page.ptr<cv::Vec3b>(chart.place.y + j) + chart.place.x;
        for (int i = 0; i < chart.size.width; ++i) {
            const int sx = std::clamp(chart.x0 + i, 0, image_size.width - 1) - origin.x;
            const cv::Vec3f& c = src[sx];
            dst[i] = cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                               cv::saturate_cast<uchar>(c[2]));
        }
    }
}

void applyChartCorrection(const Chart& chart,
                          const std::vector<std::array<Eigen::Vector2f, 3>>& face_pixels,
                          const std::vector<std::array<Vec3f, 3>>& corner_correction,
                          cv::Mat& page, bool log_gain) {
    const int w = chart.size.width, h = chart.size.height;
    std::vector<Vec3f> g(static_cast<std::size_t>(w) * h, Vec3f::Zero());
    std::vector<char> known(g.size(), 0);
    std::deque<int> frontier;
    const Eigen::Vector2f origin(static_cast<float>(chart.x0), static_cast<float>(chart.y0));
    Vec3f mean = Vec3f::Zero();
    for (std::uint32_t f : chart.faces) {
        std::array<Eigen::Vector2f, 3> local;
        for (int k = 0; k < 3; ++k) {
            local[k] = face_pixels[f][k] - origin;
            mean += corner_correction[f][k];
        }
        rasterizeSpans(local, w, h, [&](int y, int x_begin, int x_end) {
            for (int x = x_begin; x < x_end; ++x) {
                // Paper Sec. 5.2.3: the pixel correction is the barycentric interpolation of
                // the corner corrections g_v.
                const Eigen::Vector3f b = barycentric(local, Eigen::Vector2f(float(x), float(y)));
                const int idx = y * w + x;
                g[idx] = b[0] * corner_correction[f][0] + b[1] * corner_correction[f][1] +
                         b[2] * corner_correction[f][2];
                if (!known[idx]) {
                    known[idx] = 1;
                    frontier.push_back(idx);
                }
            }
        });
    }
    if (frontier.empty()) {
        mean /= static_cast<float>(3 * std::max<std::size_t>(chart.faces.size(), 1));
        std::fill(g.begin(), g.end(), mean);
    } else {
        while (!frontier.empty()) {
            const int idx = frontier.front();
            frontier.pop_front();
            const int x = idx % w, y = idx / w;
            const int neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
            for (const auto& n : neighbours) {
                if (n[0] < 0 || n[1] < 0 || n[0] >= w || n[1] >= h) continue;
                const int nidx = n[1] * w + n[0];
                if (known[nidx]) continue;
                known[nidx] = 1;
                g[nidx] = g[idx];
                frontier.push_back(nidx);
            }
        }
    }
    for (int y = 0; y < h; ++y) {
        auto* dst = page.ptr<cv::Vec3b>(chart.place.y + y) + chart.place.x;
        for (int x = 0; x < w; ++x) {
            const Vec3f& c = g[static_cast<std::size_t>(y) * w + x];
            for (int k = 0; k < 3; ++k) {
                dst[x][k] = cv::saturate_cast<uchar>(log_gain ? dst[x][k] * std::exp(c[k])
                                                              : dst[x][k] + c[k]);
            }
        }
    }
}

void faceUvs(const AtlasLayout& layout,
             const std::vector<std::array<Eigen::Vector2f, 3>>& face_pixels,
             std::vector<std::array<Eigen::Vector2f, 3>>& uvs, std::vector<std::uint32_t>& pages,
             const std::vector<std::uint32_t>& face_fill_cell) {
    const std::size_t num_faces = layout.face_chart.size();
    uvs.resize(num_faces);
    pages.resize(num_faces);
    auto toUv = [&](int page, float X, float Y) {
        const RectSize& s = layout.pages[page];
        return Eigen::Vector2f((X + 0.5f) / s.width, 1.0f - (Y + 0.5f) / s.height);
    };
    for (std::size_t f = 0; f < num_faces; ++f) {
        const std::uint32_t c = layout.face_chart[f];
        if (c == kNoLabel) {
            const int cell = face_fill_cell.empty() ? 0 : static_cast<int>(face_fill_cell[f]);
            const RectPlacement origin = fillCellOrigin(layout, cell);
            const float centre = 0.5f * (kFillCellPx - 1);
            const Eigen::Vector2f uv = toUv(origin.page, origin.x + centre, origin.y + centre);
            uvs[f] = {uv, uv, uv};
            pages[f] = static_cast<std::uint32_t>(layout.fill_place.page);
            continue;
        }
        const Chart& chart = layout.charts[c];
        for (int k = 0; k < 3; ++k) {
            const Eigen::Vector2f& p = face_pixels[f][k];
            uvs[f][k] = toUv(chart.place.page, chart.place.x + p.x() - chart.x0,
                             chart.place.y + p.y() - chart.y0);
        }
        pages[f] = static_cast<std::uint32_t>(chart.place.page);
    }
}

}  // namespace vdbmap::texture
