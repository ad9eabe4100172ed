// SPDX-License-Identifier: Apache-2.0
#include "Lod.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <unordered_map>

#include <meshoptimizer.h>

#include "Bake.h"
#include "vdbmap/core/Timer.h"

namespace vdbmap::tiles3d {
namespace {

struct PositionKeyHash {
    std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
        std::uint64_t h = 1469598103934665603ull;
        for (const std::int64_t v : k) h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

}  // namespace

std::vector<std::array<Eigen::Vector3d, 3>> trianglesW(const TileMesh& mesh) {
    std::vector<std::array<Eigen::Vector3d, 3>> t(mesh.faces());
    for (std::size_t f = 0; f < mesh.faces(); ++f) {
        for (int k = 0; k < 3; ++k) t[f][static_cast<std::size_t>(k)] = mesh.cornerW(f, k);
    }
    return t;
}

TileMesh buildParent(const std::vector<const TileMesh*>& children, const ParentOptions& options,
                     ParentFigures* figures, const TriangleGrid* children_grid) {
    Timer step;
    TileMesh parent;
    Bounds bounds;
    for (const TileMesh* c : children) bounds.add(boundsW(*c));
    parent.origin_W = bounds.empty() ? Eigen::Vector3d::Zero()
                                     : Eigen::Vector3d((0.5 * (bounds.min_W + bounds.max_W)).array().round());

    // Weld by position only: texture seams and class borders are no borders for the
    // simplification (the parent gets its own atlas and classes below).
    // (Vertex ids in order of first appearance: the hash map only answers lookups.)
    std::unordered_map<std::array<std::int64_t, 3>, std::uint32_t, PositionKeyHash> index_of;
    std::size_t corner_count = 0;
    for (const TileMesh* c : children) corner_count += 3 * c->faces();
    index_of.reserve(corner_count / 2);
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::size_t merged = 0;
    double area_m2 = 0, area_px = 0;  // the children's texel size (texelSizeM over all)
    for (const TileMesh* c : children) {
        merged += c->faces();
        const double t = texelSizeM(*c);
        if (t > 0) {
            double a = 0;
            for (std::size_t f = 0; f < c->faces(); ++f) {
                if (c->page[f] == kNoPage) continue;
                const auto& q = c->corners[f];
                a += 0.5 * static_cast<double>((q[1] - q[0]).cross(q[2] - q[0]).norm());
            }
            area_m2 += a;
            area_px += a / (t * t);
        }
        for (std::size_t f = 0; f < c->faces(); ++f) {
            for (int k = 0; k < 3; ++k) {
                const Eigen::Vector3d w = c->cornerW(f, k);
                const std::array<std::int64_t, 3> key{std::llround(w.x() * 1e4), std::llround(w.y() * 1e4),
                                                      std::llround(w.z() * 1e4)};
                const auto [it, added] = index_of.emplace(key, static_cast<std::uint32_t>(positions.size() / 3));
                if (added) {
                    const Eigen::Vector3f p = (w - parent.origin_W).cast<float>();
                    positions.insert(positions.end(), {p.x(), p.y(), p.z()});
                }
                indices.push_back(it->second);
            }
        }
    }
    index_of.clear();
    const std::size_t vertex_count = positions.size() / 3;
    const double weld_s = step.elapsedSeconds();
    step.reset();

    // A quarter of the faces, at most voxel_size_m * 2^level of error. No LockBorder: it would
    // lock every open border of the mesh too (meshoptimizer 0.18 cannot lock a chosen subset),
    // and the levels above 2 would barely simplify; border vertices still collapse only along
    // the border, onto border vertices (docs/tiles3d.md, "Levels of detail").
    std::vector<std::uint32_t> simplified(indices.size());
    std::size_t count = 0;
    if (!indices.empty()) {
        const float mesh_scale = meshopt_simplifyScale(positions.data(), vertex_count, 12);
        const double max_error_m = options.voxel_size_m * std::pow(2.0, options.level);
        const std::size_t target = std::max<std::size_t>(3, indices.size() / 3 / 4 * 3);
        float error_rel = 0;
        count = meshopt_simplify(simplified.data(), indices.data(), indices.size(), positions.data(),
                                 vertex_count, 12, target,
                                 static_cast<float>(max_error_m / std::max(1e-9f, mesh_scale)),
                                 0, &error_rel);
        if (figures) figures->simplify_error_m = error_rel * mesh_scale;
    }
    const std::size_t n = count / 3;
    parent.corners.resize(n);
    for (std::size_t f = 0; f < n; ++f) {
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t v = simplified[3 * f + k];
            parent.corners[f][k] = Eigen::Vector3f(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
        }
    }

    const double simplify_s = step.elapsedSeconds();
    step.reset();

    // A fresh atlas at twice the children's texel size, baked from them.
    const double child_texel_m = area_px > 0 ? std::sqrt(area_m2 / area_px) : 0.0;
    BakeFigures bake;
    bakeAtlas(parent, children, 2.0 * child_texel_m, options.max_atlas_px, options.gutter_px, &bake, children_grid);
    if (figures) {
        figures->merged_faces = merged;
        figures->faces = n;
        figures->child_texel_m = child_texel_m;
        figures->texel_m = bake.texel_m;
        figures->texels = bake.texels;
        figures->charts = bake.charts;
        figures->max_texel_distance_m = bake.max_texel_distance_m;
        figures->weld_s = weld_s;
        figures->simplify_s = simplify_s;
        figures->bake_s = step.elapsedSeconds();
    }
    return parent;
}

}  // namespace vdbmap::tiles3d
