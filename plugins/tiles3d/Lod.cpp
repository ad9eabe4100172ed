// SPDX-License-Identifier: Apache-2.0
#include "Lod.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include <meshoptimizer.h>
#include <opencv2/imgproc.hpp>

namespace vdbmap::tiles3d {
namespace {

struct Placement {
    int x = 0, y = 0, w = 0, h = 0;
};

/// Shelf packing of w x h rectangles (2 px apart); returns the page size.
cv::Size packShelves(const std::vector<cv::Size>& sizes, std::vector<Placement>& out) {
    out.assign(sizes.size(), {});
    double area = 0;
    int widest = 1;
    for (const cv::Size& s : sizes) {
        area += double(s.width + 2) * (s.height + 2);
        widest = std::max(widest, s.width + 2);
    }
    const int limit = std::max(widest, static_cast<int>(std::ceil(std::sqrt(area) * 1.05)));
    std::vector<std::size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return sizes[a].height > sizes[b].height; });
    int x = 0, y = 0, shelf = 0, width = 1;
    for (const std::size_t i : order) {
        const cv::Size& s = sizes[i];
        if (x > 0 && x + s.width + 2 > limit) {
            y += shelf;
            x = 0;
            shelf = 0;
        }
        out[i] = {x + 1, y + 1, s.width, s.height};
        x += s.width + 2;
        shelf = std::max(shelf, s.height + 2);
        width = std::max(width, x);
    }
    return {width, std::max(1, y + shelf)};
}

}  // namespace

std::vector<std::array<Eigen::Vector3d, 3>> trianglesW(const TileMesh& mesh) {
    std::vector<std::array<Eigen::Vector3d, 3>> t(mesh.faces());
    for (std::size_t f = 0; f < mesh.faces(); ++f) {
        for (int k = 0; k < 3; ++k) t[f][static_cast<std::size_t>(k)] = mesh.cornerW(f, k);
    }
    return t;
}

TileMesh buildParent(const std::vector<const TileMesh*>& children, const ParentOptions& options,
                     ParentFigures* figures) {
    TileMesh parent;
    Bounds bounds;
    for (const TileMesh* c : children) bounds.add(boundsW(*c));
    parent.origin_W = bounds.empty() ? Eigen::Vector3d::Zero()
                                     : Eigen::Vector3d((0.5 * (bounds.min_W + bounds.max_W)).array().round());

    // The atlas: every child page, scaled, on one page.
    std::vector<cv::Size> sizes;
    std::vector<std::size_t> first_page;  // per child: index of its first page in `sizes`
    for (const TileMesh* c : children) {
        first_page.push_back(sizes.size());
        for (const cv::Mat& p : c->pages) sizes.push_back(p.size());
    }
    std::vector<Placement> place;
    double scale = 0.5;
    cv::Size page_size(0, 0);
    if (!sizes.empty()) {
        for (;;) {
            std::vector<cv::Size> scaled;
            for (const cv::Size& s : sizes) {
                scaled.emplace_back(std::max(1, static_cast<int>(std::lround(s.width * scale))),
                                    std::max(1, static_cast<int>(std::lround(s.height * scale))));
            }
            page_size = packShelves(scaled, place);
            if (std::max(page_size.width, page_size.height) <= options.max_atlas_px || scale < 1e-3) break;
            scale *= 0.5;
        }
        cv::Mat page(page_size, CV_8UC3, cv::Scalar(0, 0, 0));
        std::size_t g = 0;
        for (const TileMesh* c : children) {
            for (const cv::Mat& p : c->pages) {
                const Placement& pl = place[g++];
                cv::Mat small;
                cv::resize(p, small, cv::Size(pl.w, pl.h), 0, 0, cv::INTER_AREA);
                small.copyTo(page(cv::Rect(pl.x, pl.y, pl.w, pl.h)));
            }
        }
        parent.pages.push_back(page);
    }

    // Weld: one vertex per (position, uv, page, class).
    struct Vertex {
        Eigen::Vector3f p;
        Eigen::Vector2f uv;
        std::uint32_t page;
        std::uint8_t label;
        float confidence;
    };
    using Key = std::tuple<std::int64_t, std::int64_t, std::int64_t, std::uint32_t, std::uint32_t,
                           std::uint32_t, std::uint8_t>;
    std::map<Key, std::uint32_t> index_of;
    std::vector<Vertex> vertices;
    std::vector<std::uint32_t> indices;
    std::size_t merged = 0;
    for (std::size_t ci = 0; ci < children.size(); ++ci) {
        const TileMesh& c = *children[ci];
        merged += c.faces();
        for (std::size_t f = 0; f < c.faces(); ++f) {
            for (int k = 0; k < 3; ++k) {
                Vertex v;
                const Eigen::Vector3d w = c.cornerW(f, k);
                v.p = (w - parent.origin_W).cast<float>();
                v.page = kNoPage;
                v.uv = Eigen::Vector2f::Zero();
                if (c.page[f] != kNoPage) {
                    const Placement& pl = place[first_page[ci] + c.page[f]];
                    const Eigen::Vector2f& uv = c.uvs[f][static_cast<std::size_t>(k)];
                    v.uv = Eigen::Vector2f((pl.x + uv.x() * pl.w) / page_size.width,
                                           (pl.y + uv.y() * pl.h) / page_size.height);
                    v.page = 0;
                }
                v.label = c.label[f];
                v.confidence = c.confidence[f];
                std::uint32_t ub, vb;
                std::memcpy(&ub, &v.uv.x(), 4);
                std::memcpy(&vb, &v.uv.y(), 4);
                // Not the class: class borders need not stay seams at a coarser level (a
                // parent's face takes the class of its first corner's face).
                const Key key{std::llround(w.x() * 1e4), std::llround(w.y() * 1e4),
                              std::llround(w.z() * 1e4), ub, vb, v.page, 0};
                const auto [it, added] = index_of.emplace(key, static_cast<std::uint32_t>(vertices.size()));
                if (added) vertices.push_back(v);
                indices.push_back(it->second);
            }
        }
    }
    index_of.clear();

    std::vector<float> positions(3 * vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        for (int a = 0; a < 3; ++a) positions[3 * i + static_cast<std::size_t>(a)] = vertices[i].p[a];
    }
    std::vector<std::uint32_t> simplified(indices.size());
    float error_rel = 0;
    std::size_t count = 0;
    if (!indices.empty()) {
        const float mesh_scale = meshopt_simplifyScale(positions.data(), vertices.size(), 12);
        const double max_error_m = options.voxel_size_m * std::pow(2.0, options.level);
        const std::size_t target = std::max<std::size_t>(3, indices.size() / 3 / 4 * 3);
        count = meshopt_simplify(simplified.data(), indices.data(), indices.size(), positions.data(),
                                 vertices.size(), 12, target,
                                 static_cast<float>(max_error_m / std::max(1e-9f, mesh_scale)),
                                 meshopt_SimplifyLockBorder, &error_rel);
        if (figures) figures->simplify_error_m = error_rel * mesh_scale;
    }
    simplified.resize(count);
    const std::size_t n = count / 3;
    parent.corners.resize(n);
    parent.label.resize(n);
    parent.confidence.resize(n);
    parent.page.resize(n);
    if (!parent.pages.empty()) parent.uvs.resize(n);
    for (std::size_t f = 0; f < n; ++f) {
        const Vertex& v0 = vertices[simplified[3 * f]];
        for (std::size_t k = 0; k < 3; ++k) {
            const Vertex& v = vertices[simplified[3 * f + k]];
            parent.corners[f][k] = v.p;
            if (!parent.pages.empty()) parent.uvs[f][k] = v.uv;
        }
        parent.label[f] = v0.label;
        parent.confidence[f] = v0.confidence;
        parent.page[f] = v0.page;
    }
    if (figures) {
        figures->merged_faces = merged;
        figures->faces = n;
        figures->texture_scale = sizes.empty() ? 0.0 : scale;
    }
    return parent;
}

}  // namespace vdbmap::tiles3d
