// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/AtsdfIntegrator.h"

#include <openvdb/openvdb.h>
#include <openvdb/tree/ValueAccessor.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>

#include "map/CellColouring.h"
#include "map/RayTraversal.h"
#include "map/LeafNeighbourhood.h"
#include "map/RayUpdate.h"
#include "map/TsdfLeafCache.h"
#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/map/BlockStats.h"
#include "vdbmap/map/CompactTsdf.h"
#include "vdbmap/map/MeasurementWeight.h"
#include "vdbmap/map/VoxelMap.h"

namespace vdbmap {

using openvdb::Coord;

namespace {

constexpr std::size_t kPointChunk = 4096;
/// Points further than this many voxels from the world origin are dropped as absurd ranges
/// (OpenVDB coordinates are 32-bit ints; the update reach must not overflow them).
constexpr float kMaxIndex = 1e9f;

/// Why a point is dropped (index + 1 into the per-chunk drop counts).
enum PointStatus : std::uint8_t { kValid = 0, kNonFinite = 1, kAtOrigin = 2, kRange = 3 };


using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Consecutive valid points [first, first + length) of one block, in scan order.
struct PointRun {
    std::uint32_t first = 0;
    std::uint32_t length = 0;
    std::int32_t slot = -1;   ///< BlockStatsGrid slot (-1: new block), then the local index
    std::uint32_t offset = 0;  ///< position of the run among its block's points
    Coord block;
};

/// The points of one block in this scan (a range of `order`) and what phase 2 derived.
struct LocalBlock {
    std::int32_t slot = -1;  ///< index into BlockStatsGrid
    std::uint32_t begin = 0, end = 0;
    Vec3d normal = Vec3d::Zero();  ///< normal used for the block's points (zero: ray direction)
    detail::CellKey cell;  ///< phase 3's schedule: colour, then cell
};

using detail::LeafNeighbourhood;

}  // namespace

/// Per-scan buffers of integrateScan, kept between scans.
struct AtsdfIntegrator::Scratch {
    std::vector<Vec3f> points_W;             ///< the LiDAR-frame overload's transformed points
    std::vector<std::vector<PointRun>> runs;  ///< per chunk of points
    std::vector<std::array<std::size_t, 3>> chunk_drops;  ///< per chunk: non-finite, origin, range
    std::vector<std::int32_t> local_of_point;  ///< local block of each point (space carving only)
    std::vector<std::int32_t> local_of_slot;  ///< block slot -> local index (-1 between scans)
    std::vector<LocalBlock> local;
    std::vector<std::uint32_t> count;
    std::vector<std::uint32_t> order;
    std::vector<Vec3f> dir;                   ///< unit ray direction per point (in `order`)
    std::vector<detail::RaySegment> segment;  ///< update segment per point (in `order`)
    std::vector<std::uint64_t> leaf_bits;     ///< LeafNeighbourhood bits per local block
    std::vector<std::uint64_t> missing_bits;  ///< those of leaves not allocated yet
    std::vector<std::uint32_t> by_cell;
    std::vector<std::uint32_t> cell_begin;
    std::vector<std::size_t> updates_per_cell;
    std::vector<TsdfLeaf*> created;           ///< leaves phase 3a added to the working tree
};

IntegrationStats& IntegrationStats::operator+=(const IntegrationStats& o) {
    scans += o.scans;
    points_in += o.points_in;
    points_integrated += o.points_integrated;
    dropped_non_finite += o.dropped_non_finite;
    dropped_at_origin += o.dropped_at_origin;
    dropped_range += o.dropped_range;
    voxel_updates += o.voxel_updates;
    carving_updates += o.carving_updates;
    bin_s += o.bin_s;
    stats_s += o.stats_s;
    alloc_s += o.alloc_s;
    update_s += o.update_s;
    retire_s += o.retire_s;
    leaves_reloaded += o.leaves_reloaded;
    leaves_retired += o.leaves_retired;
    return *this;
}

void validateAtsdfConfig(const AtsdfConfig& c, const std::string& who) {
    validateTruncation(c.truncation, who);
    auto bad = [&](const char* key, double value, const char* rule) {
        std::ostringstream os;
        os << who << ": option '" << key << "' must be " << rule << ", got " << value;
        throw ConfigError(os.str());
    };
    if (c.min_points_for_pca < 3) bad("min_points_for_pca", c.min_points_for_pca, ">= 3");
    if (!(c.weight_floor > 0.0 && c.weight_floor <= 1.0))
        bad("weight_floor", c.weight_floor, "in (0, 1]");
    if (!(c.max_weight > 0.0) || !std::isfinite(c.max_weight))
        bad("max_weight", c.max_weight, "finite and > 0");
    if (!(c.min_range_m >= 0.0)) bad("min_range_m", c.min_range_m, ">= 0");
    if (!(c.max_range_m > c.min_range_m)) bad("max_range_m", c.max_range_m, "> min_range_m");
    if (c.working_set_scans < 1) bad("working_set_scans", c.working_set_scans, ">= 1");
}

AtsdfIntegrator::AtsdfIntegrator(VoxelMap& map, const AtsdfConfig& config)
    : map_(map), config_(config), scratch_(std::make_unique<Scratch>()) {
    validateAtsdfConfig(config_, "integrate.atsdf");
    // The packed voxels hold |D| <= sdf range and W <= weight range (vdbmap/map/TsdfVoxel.h).
    const TsdfCodec& codec = map_.codec();
    if (config_.truncation.max_m > static_cast<double>(codec.sdfRange()) * (1.0 + 1e-6)) {
        std::ostringstream os;
        os << "integrate.atsdf: truncation_max_m " << config_.truncation.max_m
           << " exceeds the map's sdf range " << codec.sdfRange() << " m";
        throw ConfigError(os.str());
    }
    if (config_.max_weight > static_cast<double>(codec.weightRange()) * (1.0 + 1e-6)) {
        std::ostringstream os;
        os << "integrate.atsdf: max_weight " << config_.max_weight
           << " exceeds the map's weight range " << codec.weightRange();
        throw ConfigError(os.str());
    }
}

AtsdfIntegrator::~AtsdfIntegrator() = default;

IntegrationStats AtsdfIntegrator::integrateScan(const std::vector<Vec3f>& points_L,
                                                const Isometry3d& T_W_L) {
    std::vector<Vec3f>& points_W = scratch_->points_W;
    points_W.resize(points_L.size());
    const Eigen::Isometry3f T = T_W_L.cast<float>();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_L.size(), kPointChunk),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i < r.end(); ++i)
                              points_W[i] = T * points_L[i];
                      });
    return integrateScan(points_W, T_W_L.translation());
}

IntegrationStats AtsdfIntegrator::integrateScan(const std::vector<Vec3f>& points_W,
                                                const Vec3d& origin_W) {
    IntegrationStats st;
    st.scans = 1;
    st.points_in = points_W.size();
    const std::size_t n_points = points_W.size();
    if (n_points == 0 || !origin_W.allFinite()) {
        st.dropped_non_finite = origin_W.allFinite() ? 0 : n_points;
        totals_ += st;
        return st;
    }
    Scratch& s = *scratch_;
    const double vs = map_.voxelSize();
    const double inv_vs = 1.0 / vs;
    const TruncationParams& trunc = config_.truncation;
    BlockStatsGrid& blocks = map_.blockStats();
    const Vec3f origin_f = origin_W.cast<float>();
    const float inv_vs_f = static_cast<float>(inv_vs);
    // Range checks on squared float ranges (no square root per point).
    const float min_range2 = static_cast<float>(config_.min_range_m * config_.min_range_m);
    const double max_range_m = std::min(config_.max_range_m, 1e18);  // its square fits a float
    const float max_range2 = static_cast<float>(max_range_m * max_range_m);
    auto t0 = Clock::now();

    // ---- Phase 1: bin the valid points by 8^3 block, in scan order within each block.
    // (a) parallel over chunks of points: classify each point and cut the chunk into runs of
    //     consecutive valid points of the same block (a scan line stays in a block for many
    //     points), looking up each run's block once;
    // (b) serial over the runs, in scan order: create the blocks first seen in this scan, give
    //     each block of the scan its local index (order of first appearance) and each run its
    //     place among the block's points;
    // (c) parallel over chunks: scatter the runs into `order`.
    // The result is the serial scan-order binning, for any thread count.
    const std::size_t n_chunks = (n_points + kPointChunk - 1) / kPointChunk;
    if (s.runs.size() < n_chunks) s.runs.resize(n_chunks);
    s.chunk_drops.assign(n_chunks, {0, 0, 0});
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_chunks, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false> index(blocks.indexTree());
        for (std::size_t c = r.begin(); c < r.end(); ++c) {
            std::vector<PointRun>& runs = s.runs[c];
            runs.clear();
            std::array<std::size_t, 3>& drops = s.chunk_drops[c];
            Coord prev_block = Coord::max();
            std::int32_t prev_slot = -1;
            bool in_run = false;
            const std::size_t end = std::min(n_points, (c + 1) * kPointChunk);
            for (std::size_t i = c * kPointChunk; i < end; ++i) {
                const Vec3f& p = points_W[i];
                if (!(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()))) {
                    ++drops[kNonFinite - 1];
                    in_run = false;
                    continue;
                }
                const float range2 = (p - origin_f).squaredNorm();
                if (range2 < min_range2) {
                    ++drops[kAtOrigin - 1];
                    in_run = false;
                    continue;
                }
                // Beyond max_range_m, or beyond the int voxel index range.
                if (range2 > max_range2 || !(std::abs(p.x() * inv_vs_f) < kMaxIndex &&
                                             std::abs(p.y() * inv_vs_f) < kMaxIndex &&
                                             std::abs(p.z() * inv_vs_f) < kMaxIndex)) {
                    ++drops[kRange - 1];
                    in_run = false;
                    continue;
                }
                const Coord block = BlockStatsGrid::blockOf(detail::voxelOf(p, inv_vs_f));
                if (block != prev_block) {
                    prev_block = block;
                    prev_slot = index.getValue(block);
                    in_run = false;
                }
                if (in_run) {
                    ++runs.back().length;
                } else {
                    runs.push_back({static_cast<std::uint32_t>(i), 1, prev_slot, 0, block});
                    in_run = true;
                }
            }
        }
    });
    s.local.clear();
    s.count.clear();
    s.local_of_slot.resize(blocks.size(), -1);
    for (std::size_t c = 0; c < n_chunks; ++c) {
        st.dropped_non_finite += s.chunk_drops[c][kNonFinite - 1];
        st.dropped_at_origin += s.chunk_drops[c][kAtOrigin - 1];
        st.dropped_range += s.chunk_drops[c][kRange - 1];
        for (PointRun& run : s.runs[c]) {
            if (run.slot < 0) {  // a block first seen in this scan: created once, in scan order
                run.slot = blocks.findOrCreate(run.block);
                if (static_cast<std::size_t>(run.slot) >= s.local_of_slot.size())
                    s.local_of_slot.resize(static_cast<std::size_t>(run.slot) + 1, -1);
            }
            std::int32_t& l = s.local_of_slot[static_cast<std::size_t>(run.slot)];
            if (l < 0) {
                l = static_cast<std::int32_t>(s.local.size());
                s.local.emplace_back();
                s.local.back().slot = run.slot;
                s.count.push_back(0);
            }
            run.slot = l;  // from here on: the local index
            run.offset = s.count[static_cast<std::size_t>(l)];
            s.count[static_cast<std::size_t>(l)] += run.length;
        }
    }
    for (const LocalBlock& b : s.local) s.local_of_slot[static_cast<std::size_t>(b.slot)] = -1;
    st.points_integrated = n_points - st.dropped_non_finite - st.dropped_at_origin - st.dropped_range;
    std::vector<LocalBlock>& local = s.local;
    if (local.empty()) {
        st.bin_s = secondsSince(t0);
        totals_ += st;
        return st;
    }
    std::vector<std::uint32_t>& order = s.order;
    order.resize(st.points_integrated);
    {
        std::uint32_t offset = 0;
        for (std::size_t b = 0; b < local.size(); ++b) {
            local[b].begin = offset;
            offset += s.count[b];
            local[b].end = offset;
        }
    }
    const bool need_local_of_point = config_.space_carving;
    if (need_local_of_point) s.local_of_point.assign(n_points, -1);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_chunks, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c < r.end(); ++c)
            for (const PointRun& run : s.runs[c]) {
                std::uint32_t* dst = order.data() + local[static_cast<std::size_t>(run.slot)].begin + run.offset;
                for (std::uint32_t k = 0; k < run.length; ++k) dst[k] = run.first + k;
                if (need_local_of_point)
                    std::fill_n(s.local_of_point.data() + run.first, run.length, run.slot);
            }
    });
    st.bin_s = secondsSince(t0);
    t0 = Clock::now();

    // ---- Phase 2 (parallel over blocks): merge statistics (Eq. 1), plane (Eq. 2, 3), eps (Eq. 4),
    // and the leaves the block's updates can touch.
    // Update reach in voxels: eps_max, one voxel of rounding at each end, one voxel of margin.
    const int reach_vox = static_cast<int>(std::ceil(trunc.max_m * inv_vs)) + 2;
    const LeafNeighbourhood hood(reach_vox);
    s.leaf_bits.assign(local.size() * hood.words, 0);
    s.dir.resize(order.size());
    s.segment.resize(order.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, local.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            LocalBlock& lb = local[b];
            BlockEntry& entry = blocks.entry(lb.slot);
            // Batch statistics of this scan's points in one pass, shifted by the first point
            // (exact up to rounding, no cancellation: the points lie within one block).
            BlockStats batch;
            batch.n = static_cast<double>(lb.end - lb.begin);
            const Vec3d shift = points_W[order[lb.begin]].cast<double>();
            Vec3d sum = Vec3d::Zero();
            double sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
            for (std::uint32_t k = lb.begin; k < lb.end; ++k) {
                const Vec3d d = points_W[order[k]].cast<double>() - shift;
                sum += d;
                sxx += d.x() * d.x(); sxy += d.x() * d.y(); sxz += d.x() * d.z();
                syy += d.y() * d.y(); syz += d.y() * d.z(); szz += d.z() * d.z();
            }
            const Vec3d mean_shifted = sum / batch.n;
            batch.mean = shift + mean_shifted;
            if (batch.n > 1.0) {
                Mat3d scatter;
                scatter << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
                batch.cov = (scatter - batch.n * mean_shifted * mean_shifted.transpose()) / (batch.n - 1.0);
            }
            entry.stats = mergeStats(entry.stats, batch);
            // A patch narrower than a quarter voxel (std. dev.) is not trusted for a normal.
            const PlaneEstimate plane =
                estimatePlane(entry.stats, origin_W, config_.min_points_for_pca, 0.25 * vs);
            entry.plane_valid = plane.valid;
            entry.normal_W = plane.normal.cast<float>();
            entry.flatness = static_cast<float>(plane.flatness);
            entry.truncation_m = static_cast<float>(truncationFor(trunc, plane, entry.stats.n));
            // Each point's update segment (RaySegment, kept for phase 3) and the leaves it
            // crosses, as bits of the block's leaf neighbourhood (eps <= eps_max keeps them
            // inside it): the leaves of the box between the start and the end voxel.
            const float eps = entry.truncation_m;
            const Coord bc = blocks.blockCoord(lb.slot);
            std::uint64_t* bits = s.leaf_bits.data() + b * hood.words;
            const std::size_t own_bit = hood.bit(0, 0, 0);
            for (std::uint32_t k = lb.begin; k < lb.end; ++k) {
                const Vec3f& p = points_W[order[k]];
                const Vec3f ray = p - origin_f;
                const Vec3f dir = ray * (1.0f / std::sqrt(ray.squaredNorm()));  // one division
                const detail::RaySegment seg = detail::RaySegment::of(p, dir, eps, inv_vs_f);
                s.dir[k] = dir;
                s.segment[k] = seg;
                const Coord c0 = seg.startVoxel();
                const Coord c1 = seg.endVoxel(dir);
                const Coord lo = BlockStatsGrid::blockOf(Coord::minComponent(c0, c1)) - bc;
                const Coord hi = BlockStatsGrid::blockOf(Coord::maxComponent(c0, c1)) - bc;
                if (lo == Coord(0) && hi == Coord(0)) {  // the common case: inside the own leaf
                    bits[own_bit / 64] |= std::uint64_t{1} << (own_bit % 64);
                    continue;
                }
                const int R = hood.radius;
                const int x0 = std::max(lo.x(), -R), x1 = std::min(hi.x(), R);
                const int y0 = std::max(lo.y(), -R), y1 = std::min(hi.y(), R);
                const int z0 = std::max(lo.z(), -R), z1 = std::min(hi.z(), R);
                for (int x = x0; x <= x1; ++x)
                    for (int y = y0; y <= y1; ++y)
                        for (int z = z0; z <= z1; ++z) {
                            const std::size_t bit = hood.bit(x, y, z);
                            bits[bit / 64] |= std::uint64_t{1} << (bit % 64);
                        }
            }
        }
    });

    // ---- Phase 2b (parallel over blocks): the normal used for each block's points. A degenerate
    // block borrows the n-weighted mean of the valid normals of its 26 neighbours (re-oriented
    // towards this scan's sensor); without any, its points fall back to the ray direction.
    // Neighbour entries are only read here (phase 2 is complete), so the result is deterministic.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, local.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false> index(blocks.indexTree());
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            LocalBlock& lb = local[b];
            const BlockEntry& entry = blocks.entry(lb.slot);
            if (entry.plane_valid) {
                lb.normal = entry.normal_W.cast<double>();
                continue;
            }
            const Coord bc = blocks.blockCoord(lb.slot);
            Vec3d sum = Vec3d::Zero();
            for (int dx = -1; dx <= 1; ++dx)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dz = -1; dz <= 1; ++dz) {
                        const std::int32_t nb = index.getValue(bc.offsetBy(dx, dy, dz));
                        if (nb < 0) continue;
                        const BlockEntry& ne = blocks.entry(nb);
                        if (!ne.plane_valid) continue;
                        Vec3d n = ne.normal_W.cast<double>();
                        if (n.dot(origin_W - ne.stats.mean) < 0.0) n = -n;
                        sum += ne.stats.n * n;
                    }
            const double norm = sum.norm();
            lb.normal = norm > 0.0 ? Vec3d(sum / norm) : Vec3d::Zero();
        }
    });
    st.stats_s = secondsSince(t0);
    t0 = Clock::now();

    // ---- Phase 3a: find the leaves that do not exist yet (parallel, read-only), then allocate
    // them (serial: tree topology changes are not thread-safe).
    TsdfTree& tsdf_tree = map_.workingTsdf()->tree();
    const TsdfCodec& codec = map_.codec();
    s.missing_bits.assign(s.leaf_bits.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, local.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        openvdb::tree::ValueAccessor<const TsdfTree, false> acc(tsdf_tree);
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            const Coord bc = blocks.blockCoord(local[b].slot);
            const std::uint64_t* bits = s.leaf_bits.data() + b * hood.words;
            std::uint64_t* missing = s.missing_bits.data() + b * hood.words;
            forEachSetBit(bits, hood.words, [&](std::size_t bit) {
                if (acc.probeConstLeaf(hood.origin(bc, bit)) == nullptr)
                    missing[bit / 64] |= std::uint64_t{1} << (bit % 64);
            });
        }
    });
    {
        // A missing leaf is new, or in the compact store: then its values come back from it.
        std::vector<TsdfLeaf*>& created = s.created;
        created.clear();
        openvdb::tree::ValueAccessor<TsdfTree> acc(tsdf_tree);
        for (std::size_t b = 0; b < local.size(); ++b) {
            const Coord bc = blocks.blockCoord(local[b].slot);
            forEachSetBit(s.missing_bits.data() + b * hood.words, hood.words, [&](std::size_t bit) {
                const Coord origin = hood.origin(bc, bit);
                if (acc.probeConstLeaf(origin) == nullptr) created.push_back(acc.touchLeaf(origin));
            });
        }
        if (map_.compactTsdf().leafCount() > 0) st.leaves_reloaded = map_.reloadIntoWorking(created);
    }
    // Every leaf a block's updates can reach is stamped with this scan (BlockLeafTable::load).
    const std::uint32_t stamp = static_cast<std::uint32_t>(totals_.scans + 1);
    st.alloc_s = secondsSince(t0);
    t0 = Clock::now();

    // ---- Phase 3b: colour the blocks by cell (2 neighbourhood radii wide) and integrate.
    const int cell_blocks = 2 * hood.radius;
    for (std::size_t b = 0; b < local.size(); ++b)
        local[b].cell = detail::cellKeyOf(blocks.blockCoord(local[b].slot), cell_blocks);
    std::vector<std::uint32_t>& by_cell = s.by_cell;
    by_cell.resize(local.size());
    for (std::size_t b = 0; b < local.size(); ++b) by_cell[b] = static_cast<std::uint32_t>(b);
    std::sort(by_cell.begin(), by_cell.end(), [&](std::uint32_t a, std::uint32_t b) {
        return local[a].cell != local[b].cell ? local[a].cell < local[b].cell : a < b;
    });
    // Cell ranges within by_cell, and the colour boundaries.
    std::vector<std::uint32_t>& cell_begin = s.cell_begin;
    cell_begin.clear();
    for (std::size_t i = 0; i < by_cell.size(); ++i)
        if (i == 0 || local[by_cell[i]].cell != local[by_cell[i - 1]].cell)
            cell_begin.push_back(static_cast<std::uint32_t>(i));
    cell_begin.push_back(static_cast<std::uint32_t>(by_cell.size()));

    const float max_weight = static_cast<float>(config_.max_weight);
    const float floor_w = static_cast<float>(config_.weight_floor);
    const float vs_f = static_cast<float>(vs);
    // The voxel updates of one cell go straight into the packed leaves of each block's
    // neighbourhood (`table`, one per task). Returns the number of updates.
    auto integrateCell = [&](std::size_t cell_index, detail::BlockLeafTable& table,
                             detail::TsdfLeafCache::Accessor& acc) -> std::size_t {
        const std::size_t updates_before = table.updates();
        for (std::uint32_t i = cell_begin[cell_index]; i < cell_begin[cell_index + 1]; ++i) {
            const std::uint32_t b = by_cell[i];
            const LocalBlock& lb = local[b];
            const float eps = blocks.entry(lb.slot).truncation_m;
            const float inv_dropoff = eps > vs_f ? 1.0f / (eps - vs_f) : 0.0f;
            // No normal (isolated degenerate block): the ray direction (sdf along the ray).
            const bool has_normal = lb.normal.squaredNorm() > 0.0;
            const Vec3f block_normal = lb.normal.cast<float>();
            table.load(blocks.blockCoord(lb.slot), s.leaf_bits.data() + b * hood.words, acc, stamp);
            for (std::uint32_t k = lb.begin; k < lb.end; ++k) {
                const Vec3f& p = points_W[order[k]];
                const Vec3f& dir = s.dir[k];
                const Vec3f normal = has_normal ? block_normal : Vec3f(-dir);
                const float w_inc = has_normal ? incidenceWeightAlongRay(normal, dir, floor_w) : 1.0f;
                detail::integrateRay(s.segment[k], p, dir, normal, w_inc, eps, vs_f, inv_dropoff, table);
            }
        }
        return table.updates() - updates_before;
    };
    const std::size_t num_cells = cell_begin.size() - 1;
    s.updates_per_cell.assign(num_cells, 0);
    std::size_t colour_start = 0;
    while (colour_start < num_cells) {
        const std::uint32_t colour = local[by_cell[cell_begin[colour_start]]].cell.colour;
        std::size_t colour_end = colour_start;
        while (colour_end < num_cells && local[by_cell[cell_begin[colour_end]]].cell.colour == colour)
            ++colour_end;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(colour_start, colour_end, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              detail::TsdfLeafCache::Accessor acc(tsdf_tree);
                              detail::BlockLeafTable table(hood, codec, max_weight);
                              for (std::size_t c = r.begin(); c < r.end(); ++c)
                                  s.updates_per_cell[c] = integrateCell(c, table, acc);
                          });
        colour_start = colour_end;
    }
    for (std::size_t u : s.updates_per_cell) st.voxel_updates += u;

    // ---- Optional space carving (serial, deterministic): free space in front of the band.
    if (config_.space_carving) {
        detail::TsdfLeafCache::Accessor acc(tsdf_tree);
        detail::TsdfLeafCache cache(codec);
        CompactTsdf& compact = map_.compactTsdf();
        openvdb::tree::ValueAccessor<const CompactTsdf::TopologyTree, false> compact_acc(compact.topology());
        const float free_sdf = static_cast<float>(trunc.max_m);
        for (std::size_t i = 0; i < n_points; ++i) {
            const std::int32_t l = s.local_of_point[i];
            if (l < 0) continue;
            const double eps = blocks.entry(local[static_cast<std::size_t>(l)].slot).truncation_m;
            const Vec3d p = points_W[i].cast<double>();
            const Vec3d ray = p - origin_W;
            const double range = ray.norm();
            if (range <= eps) continue;
            detail::traverseSegment(origin_W, ray / range, range - eps - vs, inv_vs,
                                    [&](const Coord& v) {
                if (cache.fetch(v, acc)) {
                    if (cache.updateObserved(v, free_sdf, 1.0f, max_weight)) ++st.carving_updates;
                } else if (std::uint32_t* value = compact.findObserved(v, compact_acc)) {
                    detail::observedAverage(*value, free_sdf, 1.0f, max_weight, codec);
                    ++st.carving_updates;
                }
            });
        }
    }
    st.update_s = secondsSince(t0);
    t0 = Clock::now();

    // ---- Phase 4: the leaves no scan of the working set could update go to the compact store.
    const std::uint32_t keep = static_cast<std::uint32_t>(config_.working_set_scans);
    if (stamp >= keep) st.leaves_retired = map_.retireWorking(stamp - keep + 1);
    st.retire_s = secondsSince(t0);
    totals_ += st;
    return st;
}

void AtsdfIntegrator::finalize() {
    map_.compact();
    // The per-voxel truncation grid is derived from the block statistics when map.vdb is
    // written (VoxelMap::truncationGrid), so it costs no memory while the map is in use.
    openvdb::MetaMap& meta = map_.metadata();
    meta.insertMeta("voxel_size_m", openvdb::DoubleMetadata(map_.voxelSize()));
    meta.insertMeta("truncation_mode",
                    openvdb::StringMetadata(truncationModeName(config_.truncation.mode)));
    meta.insertMeta("truncation_min_m", openvdb::DoubleMetadata(config_.truncation.min_m));
    meta.insertMeta("truncation_max_m", openvdb::DoubleMetadata(config_.truncation.max_m));
    meta.insertMeta("flatness_k", openvdb::DoubleMetadata(config_.truncation.flatness_k));
    meta.insertMeta("reference_points", openvdb::DoubleMetadata(config_.truncation.reference_points));
    meta.insertMeta("weight_floor", openvdb::DoubleMetadata(config_.weight_floor));
    meta.insertMeta("max_weight", openvdb::DoubleMetadata(config_.max_weight));
    meta.insertMeta("space_carving", openvdb::BoolMetadata(config_.space_carving));
    meta.insertMeta("scans_integrated", openvdb::Int64Metadata(static_cast<std::int64_t>(totals_.scans)));
}

}  // namespace vdbmap
