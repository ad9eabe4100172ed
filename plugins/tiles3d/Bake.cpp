// SPDX-License-Identifier: Apache-2.0
#include "Bake.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "Lod.h"
#include "MeshDistance.h"

namespace vdbmap::tiles3d {
namespace {

/// A face laid flat: corner `first` at (0, 0), the next at (length, 0), the third at (cx, cy),
/// cy >= 0 (the longest edge along x, so 0 <= cx <= length).
struct Flat {
    int first = 0;
    double length = 0, cx = 0, cy = 0;
    int w = 1, h = 1;  ///< rectangle in texels, margins included
    int x = 0, y = 0;  ///< its place on the page
};

Flat layFlat(const std::array<Eigen::Vector3f, 3>& c) {
    Flat f;
    double longest = -1;
    for (int k = 0; k < 3; ++k) {
        const double l = (c[static_cast<std::size_t>((k + 1) % 3)] - c[static_cast<std::size_t>(k)]).cast<double>().norm();
        if (l > longest) {
            longest = l;
            f.first = k;
        }
    }
    const Eigen::Vector3d a = c[static_cast<std::size_t>(f.first)].cast<double>();
    const Eigen::Vector3d b = c[static_cast<std::size_t>((f.first + 1) % 3)].cast<double>();
    const Eigen::Vector3d p = c[static_cast<std::size_t>((f.first + 2) % 3)].cast<double>();
    f.length = longest;
    if (longest > 0) {
        const Eigen::Vector3d e = (b - a) / longest;
        f.cx = std::clamp((p - a).dot(e), 0.0, longest);
        f.cy = (p - a).cross(e).norm();
    }
    return f;
}

/// Shelf packing (tallest first) of the rectangles, no gaps (the margins are inside them);
/// returns the page size.
cv::Size pack(std::vector<Flat>& flats) {
    double area = 0;
    int widest = 1;
    for (const Flat& f : flats) {
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
        Flat& f = flats[i];
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
               int max_page_px, int gutter_px, BakeFigures* figures) {
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
            triangles.push_back({m.cornerW(f, 0), m.cornerW(f, 1), m.cornerW(f, 2)});
            origin.emplace_back(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(f));
            textured = textured || (m.page[f] != kNoPage && !m.uvs.empty());
        }
    }
    if (n == 0 || triangles.empty()) return;
    const TriangleGrid grid(std::move(triangles));
    textured = textured && texel_m > 0;

    // The layout: one rectangle per face, texel_m grown until the page fits.
    std::vector<Flat> flats(n);
    for (std::size_t f = 0; f < n; ++f) flats[f] = layFlat(target.corners[f]);
    cv::Size size(0, 0);
    const int g = std::max(0, gutter_px);
    if (textured) {
        for (int attempt = 0;; ++attempt) {
            for (Flat& fl : flats) {
                // Even sizes (so even places): JPEG's 2 x 2 chroma blocks never straddle two
                // faces' rectangles.
                fl.w = (std::max(1, static_cast<int>(std::ceil(fl.length / texel_m))) + 2 * g + 1) & ~1;
                fl.h = (std::max(1, static_cast<int>(std::ceil(fl.cy / texel_m))) + 2 * g + 1) & ~1;
            }
            size = pack(flats);
            const int side = std::max(size.width, size.height);
            if (side <= max_page_px || attempt > 60) break;
            texel_m *= std::max(1.02, 1.02 * double(side) / max_page_px);
        }
        target.pages.emplace_back(size, CV_8UC3, cv::Scalar(0, 0, 0));
        target.uvs.resize(n);
    }
    cv::Mat* page = textured ? &target.pages.front() : nullptr;

    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 32), [&](const auto& range) {
        std::vector<std::pair<std::uint8_t, float>> votes;
        for (std::size_t f = range.begin(); f != range.end(); ++f) {
            const Flat& fl = flats[f];
            const Triangle t{target.cornerW(f, 0), target.cornerW(f, 1), target.cornerW(f, 2)};
            // The face's corners in the flat frame's order: a, b, c.
            const Eigen::Vector3d& a = t[static_cast<std::size_t>(fl.first)];
            const Eigen::Vector3d& b = t[static_cast<std::size_t>((fl.first + 1) % 3)];
            const Eigen::Vector3d& c = t[static_cast<std::size_t>((fl.first + 2) % 3)];
            const Triangle flat{Eigen::Vector3d::Zero(), Eigen::Vector3d(fl.length, 0, 0),
                                Eigen::Vector3d(fl.cx, fl.cy, 0)};
            // Nearest source point of a W point (a local search in the grid's cells, the
            // previous texel's triangle tried first): its colour, class and confidence.
            int hint = -1;
            auto sample = [&](const Eigen::Vector3d& p, cv::Vec3b* colour, std::uint8_t* label, float* conf) {
                Eigen::Vector3d q;
                const int i = grid.nearest(p, q, hint);
                if (i < 0) return false;
                hint = i;
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
            votes.clear();
            if (page) {
                target.page[f] = 0;
                const double inv_w = 1.0 / page->cols, inv_h = 1.0 / page->rows;
                const Eigen::Vector2d flat2[3] = {{0, 0}, {fl.length, 0}, {fl.cx, fl.cy}};
                for (int k = 0; k < 3; ++k) {
                    const int corner = (fl.first + k) % 3;
                    target.uvs[f][static_cast<std::size_t>(corner)] =
                        Eigen::Vector2f(static_cast<float>((fl.x + g + flat2[k].x() / texel_m) * inv_w),
                                        static_cast<float>((fl.y + g + flat2[k].y() / texel_m) * inv_h));
                }
                for (int r = 0; r < fl.h; ++r) {
                    for (int col = 0; col < fl.w; ++col) {
                        const Eigen::Vector3d q((col + 0.5 - g) * texel_m, (r + 0.5 - g) * texel_m, 0);
                        const Eigen::Vector3d on = closestPointOnTriangle(q, flat);
                        const bool inside = (on - q).squaredNorm() < 1e-18;
                        const Eigen::Vector3d w = barycentric(on, flat);
                        const Eigen::Vector3d p = w[0] * a + w[1] * b + w[2] * c;
                        cv::Vec3b colour = kUntexturedBgr;
                        std::uint8_t label = 255;
                        float conf = 0;
                        if (sample(p, &colour, &label, &conf) && inside) votes.emplace_back(label, conf);
                        page->at<cv::Vec3b>(fl.y + r, fl.x + col) = colour;
                    }
                }
            }
            if (votes.empty()) {
                std::uint8_t label = 255;
                float conf = 0;
                if (sample((t[0] + t[1] + t[2]) / 3.0, nullptr, &label, &conf)) votes.emplace_back(label, conf);
            }
            if (votes.empty()) continue;
            std::sort(votes.begin(), votes.end(),
                      [](const auto& x, const auto& y) { return x.first < y.first; });
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
        }
    });
    if (figures) {
        figures->texel_m = textured ? texel_m : 0.0;
        figures->page_width = size.width;
        figures->page_height = size.height;
        std::size_t texels = 0;
        if (textured) {
            for (const Flat& fl : flats) texels += std::size_t(fl.w) * std::size_t(fl.h);
        }
        figures->texels = texels;
    }
}

}  // namespace vdbmap::tiles3d
