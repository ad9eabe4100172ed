// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/ScanObjects.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "vdbmap/core/UnionFind.h"
#include "vdbmap/dynamic/VoxelTable.h"

namespace vdbmap {

namespace {

/// Ground height per point: the lowest z per cell, then the least over the neighbouring cells of
/// (lowest z + slope * distance). Cells on a dense grid over the scan's xy bounding box.
std::vector<float> groundHeight(const std::vector<Vec3f>& points_L, const ScanObjectConfig& c) {
    std::vector<float> height(points_L.size(), 0.0f);
    if (points_L.empty()) return height;
    const float cell = static_cast<float>(c.ground_cell_m);
    float x0 = std::numeric_limits<float>::max(), y0 = x0, x1 = -x0, y1 = -x0;
    for (const Vec3f& p : points_L) {
        x0 = std::min(x0, p.x());
        y0 = std::min(y0, p.y());
        x1 = std::max(x1, p.x());
        y1 = std::max(y1, p.y());
    }
    const int nx = static_cast<int>((x1 - x0) / cell) + 1;
    const int ny = static_cast<int>((y1 - y0) / cell) + 1;
    const float kEmpty = std::numeric_limits<float>::max();
    std::vector<float> lowest(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), kEmpty);
    std::vector<std::uint32_t> cell_of(points_L.size());
    // Dividing by a power of two (the 1 m default) is multiplying by its inverse, exactly:
    // then no division per point.
    int exponent = 0;
    const bool power_of_two = std::frexp(cell, &exponent) == 0.5f;
    const float inv_cell = 1.0f / cell;
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        const float fx = points_L[i].x() - x0, fy = points_L[i].y() - y0;
        const int ix = std::min(nx - 1, static_cast<int>(power_of_two ? fx * inv_cell : fx / cell));
        const int iy = std::min(ny - 1, static_cast<int>(power_of_two ? fy * inv_cell : fy / cell));
        cell_of[i] = static_cast<std::uint32_t>(iy * nx + ix);
        float& l = lowest[cell_of[i]];
        l = std::min(l, points_L[i].z());
    }
    // Separable: the least over a square of (z + slope * Chebyshev distance) is the least over
    // rows of the least over columns (the distance term is max(|di|, |dj|) <= |di| + |dj|; the
    // sum is a slightly looser slope on the diagonals, which is fine).
    const int r = std::max(0, c.ground_radius_cells);
    const float step = static_cast<float>(c.ground_slope * c.ground_cell_m);
    std::vector<float> tmp(lowest.size(), kEmpty), ground(lowest.size(), kEmpty);
    for (int y = 0; y < ny; ++y) {
        for (int x = 0; x < nx; ++x) {
            float v = kEmpty;
            for (int d = -r; d <= r; ++d) {
                const int xx = x + d;
                if (xx < 0 || xx >= nx) continue;
                const float l = lowest[static_cast<std::size_t>(y * nx + xx)];
                if (l != kEmpty) v = std::min(v, l + step * static_cast<float>(std::abs(d)));
            }
            tmp[static_cast<std::size_t>(y * nx + x)] = v;
        }
    }
    for (int y = 0; y < ny; ++y) {
        for (int x = 0; x < nx; ++x) {
            float v = kEmpty;
            for (int d = -r; d <= r; ++d) {
                const int yy = y + d;
                if (yy < 0 || yy >= ny) continue;
                const float l = tmp[static_cast<std::size_t>(yy * nx + x)];
                if (l != kEmpty) v = std::min(v, l + step * static_cast<float>(std::abs(d)));
            }
            ground[static_cast<std::size_t>(y * nx + x)] = v;
        }
    }
    for (std::size_t i = 0; i < points_L.size(); ++i) height[i] = ground[cell_of[i]];
    return height;
}

}  // namespace

ScanObjects findScanObjects(const std::vector<Vec3f>& points_L, const std::vector<std::uint8_t>& dynamic,
                            const Isometry3d& T_W_L, const ScanObjectConfig& c) {
    ScanObjects out;
    const std::size_t n = points_L.size();
    out.cluster.assign(n, ScanObjects::kGround);
    if (n == 0) return out;
    const std::vector<float> ground = groundHeight(points_L, c);

    // Voxels of the points above the ground band.
    const float inv = static_cast<float>(1.0 / c.voxel_m);
    const float band = static_cast<float>(c.ground_band_m), low = static_cast<float>(c.low_band_min_m);
    std::vector<std::uint32_t> voxel_of(n, ~std::uint32_t(0));
    std::vector<std::array<std::int32_t, 3>> coords;
    VoxelTable table(n + 16);  // at most one voxel per point: never full
    std::uint64_t last_key = ~std::uint64_t(0);  // a scan's next point is often in the same voxel
    std::uint32_t last_id = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3f& p = points_L[i];
        const float above = p.z() - ground[i];
        if (above < band) {
            if (above > low) out.cluster[i] = ScanObjects::kLow;
            continue;
        }
        const std::array<std::int32_t, 3> v{static_cast<std::int32_t>(std::floor(p.x() * inv)),
                                            static_cast<std::int32_t>(std::floor(p.y() * inv)),
                                            static_cast<std::int32_t>(std::floor(p.z() * inv))};
        const std::uint64_t key = voxelKey(v[0], v[1], v[2]);
        if (key != last_key) {
            const auto next = static_cast<std::uint32_t>(coords.size());
            last_id = table.insert(key, next);
            last_key = key;
            if (last_id == next) coords.push_back(v);
        }
        voxel_of[i] = last_id;
    }
    // Connected components over the 26-neighbourhood (union-find, the lower index the root),
    // each pair of neighbours once: the 13 offsets after (0, 0, 0) in (z, y, x) order. A voxel's
    // key plus an offset's delta is its neighbour's key (the fields never wrap: voxelKey), so
    // one walk over the sorted keys per offset finds every pair, in memory order, instead of 13
    // hash probes per voxel. The components do not depend on the order of the unions.
    std::vector<std::uint32_t> parent = makeDisjointSets(coords.size());
    std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted(coords.size());
    for (std::uint32_t v = 0; v < coords.size(); ++v) {
        sorted[v] = {voxelKey(coords[v][0], coords[v][1], coords[v][2]), v};
    }
    std::sort(sorted.begin(), sorted.end());
    for (int dz = -1; dz <= 1; ++dz) {
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                if (dz < 0 || (dz == 0 && (dy < 0 || (dy == 0 && dx <= 0)))) continue;
                const std::uint64_t delta = voxelKey(dx, dy, dz) - voxelKey(0, 0, 0);  // mod 2^64
                std::size_t j = 0;
                for (std::size_t i = 0; i < sorted.size(); ++i) {
                    const std::uint64_t target = sorted[i].first + delta;
                    while (j < sorted.size() && sorted[j].first < target) ++j;
                    if (j == sorted.size()) break;
                    if (sorted[j].first == target) uniteSets(parent, sorted[i].second, sorted[j].second);
                }
            }
        }
    }
    // Clusters numbered by their first point in scan order.
    std::vector<std::int32_t> cluster_of_root(coords.size(), -1);
    std::vector<Vec3d> sum;
    std::uint32_t last_voxel = ~std::uint32_t(0), last_root = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (voxel_of[i] == ~std::uint32_t(0)) continue;
        if (voxel_of[i] != last_voxel) {
            last_voxel = voxel_of[i];
            last_root = findRoot(parent, last_voxel);
        }
        std::int32_t& k = cluster_of_root[last_root];
        const Vec3d p_W = T_W_L * points_L[i].cast<double>();
        if (k < 0) {
            k = static_cast<std::int32_t>(out.clusters.size());
            ScanCluster sc;
            sc.min_L = sc.max_L = points_L[i];
            sc.min_W = sc.max_W = p_W;
            out.clusters.push_back(sc);
            sum.push_back(Vec3d::Zero());
        }
        out.cluster[i] = k;
        ScanCluster& sc = out.clusters[static_cast<std::size_t>(k)];
        sc.min_L = sc.min_L.cwiseMin(points_L[i]);
        sc.max_L = sc.max_L.cwiseMax(points_L[i]);
        sc.min_W = sc.min_W.cwiseMin(p_W);
        sc.max_W = sc.max_W.cwiseMax(p_W);
        ++sc.points;
        sc.dynamic_points += dynamic[i] ? 1u : 0u;
        sum[static_cast<std::size_t>(k)] += points_L[i].cast<double>();
    }
    for (std::size_t k = 0; k < out.clusters.size(); ++k) {
        ScanCluster& sc = out.clusters[k];
        sc.centroid_W = T_W_L * (sum[k] / static_cast<double>(sc.points));
        const Vec3f size = sc.max_L - sc.min_L;
        const double extent = std::hypot(static_cast<double>(size.x()), static_cast<double>(size.y()));
        sc.extent_m = static_cast<float>(extent);
        sc.compact = extent <= c.max_extent_m;
        sc.confirmed = sc.compact && static_cast<int>(sc.dynamic_points) >= c.min_points &&
                       static_cast<double>(sc.dynamic_points) >= c.min_fraction * static_cast<double>(sc.points);
    }
    return out;
}

std::vector<std::uint8_t> lowPointsUnder(const std::vector<Vec3f>& points_L, const ScanObjects& objects,
                                         const std::vector<std::uint8_t>& moving, float grow_m) {
    std::vector<std::uint8_t> out(points_L.size(), 0);
    std::vector<std::size_t> boxes;
    for (std::size_t k = 0; k < moving.size(); ++k) {
        if (moving[k]) boxes.push_back(k);
    }
    if (boxes.empty()) return out;
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        if (objects.cluster[i] != ScanObjects::kLow) continue;
        const Vec3f& p = points_L[i];
        for (const std::size_t k : boxes) {
            const ScanCluster& c = objects.clusters[k];
            if (p.x() >= c.min_L.x() - grow_m && p.x() <= c.max_L.x() + grow_m &&
                p.y() >= c.min_L.y() - grow_m && p.y() <= c.max_L.y() + grow_m) {
                out[i] = 1;
                break;
            }
        }
    }
    return out;
}

std::vector<std::uint8_t> pointsNearDynamic(const std::vector<Vec3f>& points_L,
                                            const std::vector<std::uint8_t>& dynamic,
                                            const ScanObjects& objects,
                                            const std::vector<std::uint8_t>& moving, float voxel_m,
                                            int rings, int min_seed_points, int down) {
    std::vector<std::uint8_t> out(points_L.size(), 0);
    const float inv = 1.0f / voxel_m;
    auto voxelOf = [&](const Vec3f& p) { return voxelCoords(p.x(), p.y(), p.z(), inv); };
    // The voxels holding a dynamic point.
    std::size_t n_dynamic = 0;
    for (const std::uint8_t d : dynamic) n_dynamic += d;
    if (n_dynamic == 0 || rings <= 0) return out;
    // Seeds: voxels with at least kSeedPoints dynamic points (a lone false detection grows
    // nothing).
    VoxelTable table(n_dynamic + 16);
    std::vector<std::uint32_t> count;
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        if (!dynamic[i]) continue;
        const auto v = voxelOf(points_L[i]);
        const auto next = static_cast<std::uint32_t>(count.size());
        const std::uint32_t id = table.insert(voxelKey(v[0], v[1], v[2]), next);
        if (id == next) count.push_back(0);
        ++count[id];
    }
    // The seeds' voxels grown by `rings` (Chebyshev distance), so that a point asks one voxel.
    std::vector<std::array<std::int64_t, 3>> seed_voxels;
    {
        VoxelTable seen(n_dynamic + 16);
        for (std::size_t i = 0; i < points_L.size(); ++i) {
            if (!dynamic[i]) continue;
            const auto v = voxelOf(points_L[i]);
            const std::uint64_t key = voxelKey(v[0], v[1], v[2]);
            if (count[static_cast<std::size_t>(table.find(key))] < static_cast<std::uint32_t>(min_seed_points)) continue;
            const auto next = static_cast<std::uint32_t>(seed_voxels.size());
            if (seen.insert(key, next) == next) seed_voxels.push_back(v);
        }
    }
    if (seed_voxels.empty()) return out;
    const auto side = static_cast<std::size_t>(2 * rings + 1);
    const int below = rings + std::max(0, down);
    VoxelTable reach(seed_voxels.size() * side * side * static_cast<std::size_t>(below + rings + 1) + 16);
    for (const auto& v : seed_voxels) {
        for (int dz = -below; dz <= rings; ++dz) {
            for (int dy = -rings; dy <= rings; ++dy) {
                for (int dx = -rings; dx <= rings; ++dx) reach.insert(voxelKey(v[0] + dx, v[1] + dy, v[2] + dz), 0);
            }
        }
    }
    std::uint64_t last_key = ~std::uint64_t(0);  // a scan's next point is often in the same voxel
    std::uint8_t last_near = 0;
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        const std::int32_t c = objects.cluster[i];
        if (dynamic[i] || c < 0 || moving[static_cast<std::size_t>(c)]) continue;
        const auto v = voxelOf(points_L[i]);
        const std::uint64_t key = voxelKey(v[0], v[1], v[2]);
        if (key != last_key) {
            last_key = key;
            last_near = reach.find(key) >= 0 ? 1 : 0;
        }
        out[i] = last_near;
    }
    return out;
}

}  // namespace vdbmap
