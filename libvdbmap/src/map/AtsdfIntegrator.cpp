// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/AtsdfIntegrator.h"

#include <openvdb/openvdb.h>
#include <openvdb/tree/ValueAccessor.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>

#include "map/CellColouring.h"
#include "map/RayTraversal.h"
#include "map/LeafNeighbourhood.h"
#include "map/PointCells.h"
#include "map/RayUpdate.h"
#include "map/TsdfLeafCache.h"
#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/map/BlockStats.h"
#include "vdbmap/map/CompactTsdf.h"
#include "vdbmap/map/MeasurementWeight.h"
#include "vdbmap/map/RingSpacing.h"
#include "vdbmap/map/VoxelMap.h"

namespace vdbmap {

using openvdb::Coord;

// Named rather than anonymous: AtsdfIntegrator::Scratch (declared in the header) holds these
// types, and a member of an anonymous-namespace type would give it internal linkage.
namespace atsdf_scan {

constexpr std::size_t kPointChunk = 4096;

using detail::kAtOrigin;
using detail::kNonFinite;
using detail::kRange;

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
    /// Its rays (gatherRays) are [begin, ray_end) of Scratch::ray_point: its points, or with
    /// merge_divisions one per cell they fall in.
    std::uint32_t ray_end = 0;
    Vec3d normal = Vec3d::Zero();  ///< normal used for the block's points (zero: ray direction)
    /// P_flat of that normal's plane (borrowed: the neighbours' n-weighted mean): the share of
    /// noise_ratio its points get (noiseWeight's variance model needs the plane to hold).
    float flatness = 0.0f;
    detail::CellKey cell;  ///< phase 3's schedule: colour, then cell
};

using detail::LeafNeighbourhood;

/// planSegments' working values of one ray.
struct RayPlan {
    float range_m = 0.0f;
    AdaptiveBand<float> band{0.0f, 0.0f, 0.0f};  ///< {front, back, reach}; paper, fixed: eps
};

/// The cells of one 8^3 block seen so far while its points are merged into rays (phase 2,
/// AtsdfConfig::merge_divisions s: cells of a voxel / s side, (8 s)^3 per block): the ray of
/// each cell (-1: none yet), the sum of its points' offsets from the ray's first point, and the
/// cells used (to reset them).
struct CellRays {
    std::vector<std::int32_t> ray;
    std::vector<Vec3f> delta_sum;
    std::vector<std::uint32_t> used;
    std::size_t n_used = 0;
    explicit CellRays(int divisions) {
        const std::size_t side = 8 * static_cast<std::size_t>(divisions);
        ray.assign(side * side * side, -1);
        delta_sum.resize(ray.size());
        used.resize(ray.size());
    }
};

/// The cells of merge_divisions s (gatherRays): a voxel / s side, (8 s)^3 per block; s = 0
/// (every point its own ray): the voxels. Cell j = floor((p / voxel + 1/2) s) (classifyPoints,
/// map/PointCells.h; voxel i covers [i - 1/2, i + 1/2)); the product is exact for s = 1, 2, so
/// the voxel is j >> (s - 1) (floor(2 x) >> 1 = floor(x)) and a point's cell lies in its voxel,
/// and so in its block.
template <int kDivisions>
struct MergeCell {
    static_assert(kDivisions >= 0 && kDivisions <= 2, "merge_divisions is 0, 1 or 2");
    static constexpr int kShift = kDivisions == 2 ? 1 : 0;
    static constexpr int kBits = 3 + kShift;  ///< 8 s cells per block side
    static constexpr int kMask = (1 << kBits) - 1;
    static Coord voxel(const Coord& cell) {
        return Coord(cell.x() >> kShift, cell.y() >> kShift, cell.z() >> kShift);
    }
    /// The cell's place in its block (its low bits, x major): CellRays' index.
    static std::uint16_t inBlock(const Coord& cell) {
        return static_cast<std::uint16_t>(((cell.x() & kMask) << (2 * kBits)) |
                                          ((cell.y() & kMask) << kBits) | (cell.z() & kMask));
    }
};

/// estimatePlane's min_spread_m: a patch narrower than a quarter voxel, or than twice the range
/// noise (one ring's points: a ribbon along the rays), is not trusted for a normal.
double minPlaneSpread(const AtsdfConfig& config, double voxel_m) {
    return std::max(0.25 * voxel_m, 2.0 * config.range_noise_m);
}

}  // namespace atsdf_scan

using namespace atsdf_scan;

/// Per-scan buffers of integrateScan, kept between scans.
struct AtsdfIntegrator::Scratch {
    explicit Scratch(int merge_divisions)
        : cell_rays([merge_divisions] { return CellRays(std::max(1, merge_divisions)); }) {}
    std::vector<Vec3f> points_W;             ///< the LiDAR-frame overload's transformed points
    std::vector<std::vector<PointRun>> runs;  ///< per chunk of points
    std::vector<std::array<std::size_t, 3>> chunk_drops;  ///< per chunk: non-finite, origin, range
    std::vector<std::int32_t> local_of_point;  ///< local block of each point (space carving only)
    std::vector<std::int32_t> local_of_slot;  ///< block slot -> local index (-1 between scans)
    std::vector<LocalBlock> local;
    std::vector<std::uint32_t> count;
    std::vector<std::uint32_t> order;
    /// Per thread: the cells of merge_divisions (gatherRays).
    tbb::enumerable_thread_specific<CellRays> cell_rays;
    /// merge_divisions > 0: each point's cell in its block (MergeCell::inBlock), from phase 1.
    std::vector<std::uint16_t> point_cell;
    std::vector<Vec3f> ray_point;             ///< per ray: its point (LocalBlock::ray_end)
    std::vector<float> ray_count;             ///< per ray: the points it stands for
    std::vector<Vec3f> dir;                   ///< unit direction per ray
    std::vector<detail::RaySegment> segment;  ///< update segment per ray
    /// Per ray, while planSegments runs: its range and its band along the ray.
    std::vector<RayPlan> plan;
    std::vector<std::uint64_t> leaf_bits;     ///< LeafNeighbourhood bits per local block
    std::vector<std::uint64_t> missing_bits;  ///< those of leaves not allocated yet
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed_blocks;  ///< (CellKey::packed, block)
    std::vector<std::uint32_t> by_cell;
    std::vector<std::uint32_t> cell_begin;
    std::vector<std::size_t> updates_per_cell;
    std::vector<TsdfLeaf*> created;           ///< leaves phase 3a added to the working tree
    bool use_rings = false;  ///< grazing_band_to_next_ring, and the scan came in its sensor frame
    RingSpacing rings;       ///< the scan's rings (use_rings)
    Vec3f up_W = Vec3f::UnitZ();  ///< the sensor's z axis in the world frame (use_rings)
};

IntegrationStats& IntegrationStats::operator+=(const IntegrationStats& o) {
    scans += o.scans;
    points_in += o.points_in;
    points_integrated += o.points_integrated;
    dropped_non_finite += o.dropped_non_finite;
    dropped_at_origin += o.dropped_at_origin;
    dropped_range += o.dropped_range;
    rays += o.rays;
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

AtsdfConfig resolveAtsdfConfig(const AtsdfConfig& config, double voxel_size_m) {
    AtsdfConfig r = config;
    r.truncation = resolveTruncation(config.truncation, voxel_size_m);
    if (r.falloff_m == 0.0) r.falloff_m = r.falloff_voxels * voxel_size_m;
    if (r.merge_divisions == kMergeAuto)
        r.merge_divisions = r.truncation.mode == TruncationMode::Adaptive ? 1 : 0;
    return r;
}

void validateAtsdfConfig(const AtsdfConfig& config, double voxel_size_m, const std::string& who) {
    auto bad = [&](const char* key, double value, const char* rule) {
        std::ostringstream os;
        os << who << ": option '" << key << "' must be " << rule << ", got " << value;
        throw ConfigError(os.str());
    };
    // The given values first (0 = from voxels or from the density), named as the stage's keys.
    const TruncationParams& t = config.truncation;
    for (const auto& [key, value] : {std::pair<const char*, double>{"truncation_min_voxels", t.min_voxels},
                                     {"truncation_max_voxels", t.max_voxels},
                                     {"truncation_min_m", t.min_m},
                                     {"truncation_max_m", t.max_m},
                                     {"grazing_band_voxels", t.grazing_band_voxels},
                                     {"reference_points", t.reference_points},
                                     {"falloff_voxels", config.falloff_voxels}}) {
        if (!(value >= 0.0) || !std::isfinite(value)) bad(key, value, "finite and >= 0");
    }
    if (!(t.reference_density_pts_m2 > 0.0) || !std::isfinite(t.reference_density_pts_m2))
        bad("reference_density_pts_m2", t.reference_density_pts_m2, "finite and > 0");
    if (config.merge_divisions < kMergeAuto || config.merge_divisions > 2)
        bad("merge_divisions", config.merge_divisions, "-1 (auto), 0, 1 or 2");
    // Then the values the integrator runs.
    const AtsdfConfig c = resolveAtsdfConfig(config, voxel_size_m);
    validateTruncation(c.truncation, who);
    if (c.min_points_for_pca < 3) bad("min_points_for_pca", c.min_points_for_pca, ">= 3");
    if (!(c.weight_floor > 0.0 && c.weight_floor <= 1.0))
        bad("weight_floor", c.weight_floor, "in (0, 1]");
    if (!(c.max_weight > 0.0) || !std::isfinite(c.max_weight))
        bad("max_weight", c.max_weight, "finite and > 0");
    if (!(c.range_noise_m >= 0.0) || !std::isfinite(c.range_noise_m))
        bad("range_noise_m", c.range_noise_m, "finite and >= 0");
    if (!(c.noise_ratio >= 0.0) || !std::isfinite(c.noise_ratio))
        bad("noise_ratio", c.noise_ratio, "finite and >= 0");
    if (!(c.falloff_m >= 0.0) || !std::isfinite(c.falloff_m)) bad("falloff_m", c.falloff_m, "finite and >= 0");
    if (!(c.min_range_m >= 0.0)) bad("min_range_m", c.min_range_m, ">= 0");
    if (!(c.max_range_m > c.min_range_m)) bad("max_range_m", c.max_range_m, "> min_range_m");
    if (c.working_set_scans < 1) bad("working_set_scans", c.working_set_scans, ">= 1");
}

const char* mergePointsName(int merge_divisions) {
    switch (merge_divisions) {
        case 0: return "none";
        case 1: return "voxel";
        case 2: return "half_voxel";
        default: return "auto";
    }
}

int parseMergePoints(const std::string& text) {
    if (text == "auto") return kMergeAuto;
    if (text == "none") return 0;
    if (text == "voxel") return 1;
    if (text == "half_voxel") return 2;
    throw ConfigError("merge_points must be auto, none, voxel or half_voxel, got '" + text + "'");
}

std::shared_ptr<VoxelMap> makeVoxelMap(const AtsdfConfig& config, double voxel_size_m) {
    const AtsdfConfig r = resolveAtsdfConfig(config, voxel_size_m);
    return std::make_shared<VoxelMap>(voxel_size_m, static_cast<float>(r.truncation.max_m),
                                      static_cast<float>(r.max_weight));
}

double mergedRayFrontExtension(const AtsdfConfig& config, double voxel_size_m) {
    const int s = resolveAtsdfConfig(config, voxel_size_m).merge_divisions;
    return s > 0 ? 0.5 * std::sqrt(3.0) * voxel_size_m / s : 0.0;
}

double maxUpdateReach(const AtsdfConfig& config, double voxel_size_m) {
    return maxHalfLength(resolveAtsdfConfig(config, voxel_size_m).truncation) +
           mergedRayFrontExtension(config, voxel_size_m);
}

AtsdfIntegrator::AtsdfIntegrator(VoxelMap& map, const AtsdfConfig& config)
    : map_(map),
      config_(resolveAtsdfConfig(config, map.voxelSize())),
      scratch_(std::make_unique<Scratch>(config_.merge_divisions)) {
    validateAtsdfConfig(config, map_.voxelSize(), "integrate.atsdf");
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
    describeMap();
}

AtsdfIntegrator::~AtsdfIntegrator() = default;

bool AtsdfIntegrator::usesRings() const {
    const TruncationParams& tp = config_.truncation;
    return tp.mode == TruncationMode::Adaptive && tp.grazing_band_to_next_ring;
}

IntegrationStats AtsdfIntegrator::integrateScan(PointSpan points_L, const Isometry3d& T_W_L) {
    return integrateScan(points_L, T_W_L, usesRings() ? RingSpacing::estimate(points_L) : RingSpacing{});
}

IntegrationStats AtsdfIntegrator::integrateScan(PointSpan points_L, const Isometry3d& T_W_L,
                                                const RingSpacing& rings) {
    std::vector<Vec3f>& points_W = scratch_->points_W;
    points_W.resize(points_L.size());
    const Eigen::Isometry3f T = T_W_L.cast<float>();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_L.size(), kPointChunk),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i < r.end(); ++i)
                              points_W[i] = T * points_L[i];
                      });
    scratch_->use_rings = usesRings() && rings.valid();
    if (scratch_->use_rings) {
        scratch_->rings = rings;
        scratch_->up_W = T.linear() * Vec3f::UnitZ();
    }
    return integrateInWorld(points_W, T_W_L.translation());
}

/// One scan's integration, phase by phase (AtsdfIntegrator.h lists the phases). Holds the
/// scan's constants and references; the buffers are the integrator's Scratch.
class AtsdfIntegrator::ScanPass {
public:
    ScanPass(VoxelMap& map, const AtsdfConfig& config, Scratch& scratch,
             const std::vector<Vec3f>& points_W, const Vec3d& origin_W, std::uint32_t stamp)
        : map_(map),
          config_(config),
          trunc_(config.truncation),
          s_(scratch),
          blocks_(map.blockStats()),
          points_W_(points_W),
          origin_W_(origin_W),
          origin_f_(origin_W.cast<float>()),
          vs_(map.voxelSize()),
          inv_vs_f_(static_cast<float>(1.0 / map.voxelSize())),
          // Update reach in voxels: the longest half-length along a ray (a merged ray's front
          // included), one voxel of rounding at each end, one voxel of margin.
          hood_(static_cast<int>(std::ceil(maxUpdateReach(config, map.voxelSize()) / map.voxelSize())) + 2),
          merged_front_m_(static_cast<float>(mergedRayFrontExtension(config, map.voxelSize()))),
          stamp_(stamp),
          min_spread_m_(minPlaneSpread(config, map.voxelSize())) {}

    /// Phase 1: classify the points (drops counted in `st`) and bin the valid ones by 8^3
    /// block in scan order. False if no point is left.
    bool bin(IntegrationStats& st);
    /// Phase 2: per block, merge this scan's batch statistics (Eq. 1), then plane (Eq. 2, 3)
    /// and eps (Eq. 4); and the rays of its points (gatherRays).
    void mergeStatistics();
    /// Phase 2b: the normal used for each block's points (degenerate blocks borrow).
    void borrowNormals();
    /// Phase 2c: each ray's update segment and the leaves the segments cross.
    void planSegments();
    /// Phase 3a: allocate the missing leaves (or reload them from the compact store).
    void allocate(IntegrationStats& st);
    /// Phase 3b: the voxel updates, colour by colour.
    void integrate(IntegrationStats& st);
    /// Optional space carving in front of the bands.
    void carve(IntegrationStats& st);
    /// Phase 4: the leaves that left the working set go to the compact store.
    void retire(IntegrationStats& st);

private:
    void classifyChunks(std::size_t n_chunks);
    using BlockIndexAccessor = openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false>;
    template <int kDivisions>
    void classifyChunk(std::size_t c, const detail::PointLimits& limits, BlockIndexAccessor& index);
    void assignLocalBlocks(std::size_t n_chunks, IntegrationStats& st);
    void scatterOrder(std::size_t n_chunks);
    std::uint32_t gatherRays(const LocalBlock& lb, CellRays* cells) const;
    void markLeaves(std::uint64_t* bits, const Coord& bc, const detail::RaySegment& seg,
                    const Vec3f& dir) const;
    bool landsOnPlane(BlockIndexAccessor& index, const Vec3f& p, const Vec3f& dir,
                      const Vec3f& normal, float t, float band) const;
    std::size_t integrateCell(std::size_t cell_index, detail::BlockLeafTable& table,
                              detail::TsdfLeafCache::Accessor& acc) const;

    VoxelMap& map_;
    const AtsdfConfig& config_;
    const TruncationParams& trunc_;
    Scratch& s_;
    BlockStatsGrid& blocks_;
    const std::vector<Vec3f>& points_W_;
    const Vec3d origin_W_;
    const Vec3f origin_f_;
    const double vs_;
    const float inv_vs_f_;
    const LeafNeighbourhood hood_;
    const float merged_front_m_;  ///< mergedRayFrontExtension
    const std::uint32_t stamp_;
    const double min_spread_m_;
};

void AtsdfIntegrator::ScanPass::classifyChunks(std::size_t n_chunks) {
    // Parallel over chunks of points; one loop per merge_divisions, so that the cell arithmetic
    // is known to the compiler.
    // Range checks on squared float ranges (no square root per point).
    const double max_range_m = std::min(config_.max_range_m, 1e18);  // its square fits a float
    detail::PointLimits limits;
    limits.origin_W = origin_f_;
    limits.min_range2 = static_cast<float>(config_.min_range_m * config_.min_range_m);
    limits.max_range2 = static_cast<float>(max_range_m * max_range_m);
    limits.inv_voxel = inv_vs_f_;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_chunks, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        BlockIndexAccessor index(blocks_.indexTree());
        for (std::size_t c = r.begin(); c < r.end(); ++c) {
            switch (config_.merge_divisions) {
                case 0: classifyChunk<0>(c, limits, index); break;
                case 1: classifyChunk<1>(c, limits, index); break;
                default: classifyChunk<2>(c, limits, index); break;
            }
        }
    });
}

template <int kDivisions>
void AtsdfIntegrator::ScanPass::classifyChunk(std::size_t c, const detail::PointLimits& limits,
                                              BlockIndexAccessor& index) {
    // Classify each point of chunk c and cut the chunk into runs of consecutive valid points of
    // the same block (a scan line stays in a block for many points), looking up each run's
    // block once. With merged rays, each point's cell in its block is kept for gatherRays. The
    // checks and cells come a batch at a time (classifyPoints: branch-free, four points at once).
    using Cell = MergeCell<kDivisions>;
    std::vector<PointRun>& runs = s_.runs[c];
    runs.clear();
    std::array<std::size_t, 3>& drops = s_.chunk_drops[c];
    std::uint16_t* cell_in_block = s_.point_cell.data();
    Coord prev_block = Coord::max();
    std::int32_t prev_slot = -1;
    bool in_run = false;
    detail::PointCells batch;
    const std::size_t end = std::min(points_W_.size(), (c + 1) * kPointChunk);
    for (std::size_t first = c * kPointChunk; first < end; first += detail::PointCells::kCapacity) {
        const std::size_t n = std::min(detail::PointCells::kCapacity, end - first);
        detail::classifyPoints<kDivisions == 2 ? 2 : 1>(points_W_.data() + first, n, limits, batch);
        for (std::size_t j = 0; j < n; ++j) {
            if (batch.status[j] != detail::kValid) {
                ++drops[static_cast<std::size_t>(batch.status[j] - 1)];
                in_run = false;
                continue;
            }
            const std::size_t i = first + j;
            const Coord cell(batch.x[j], batch.y[j], batch.z[j]);
            const Coord block = BlockStatsGrid::blockOf(Cell::voxel(cell));
            if constexpr (kDivisions > 0) cell_in_block[i] = Cell::inBlock(cell);
            if (block != prev_block) {
                prev_block = block;
                prev_slot = index.getValue(block);
                in_run = false;
            }
            if (in_run) {
                ++runs.back().length;
            } else {
                // Field by field into the vector: a braced temporary was built on the stack and
                // copied in 16-byte pieces, which stalled on its 4-byte stores (store forwarding).
                PointRun& run = runs.emplace_back();
                run.first = static_cast<std::uint32_t>(i);
                run.length = 1;
                run.slot = prev_slot;
                run.block = block;
                in_run = true;
            }
        }
    }
}

void AtsdfIntegrator::ScanPass::assignLocalBlocks(std::size_t n_chunks, IntegrationStats& st) {
    // Serial over the runs, in scan order: create the blocks first seen in this scan, give each
    // block of the scan its local index (order of first appearance) and each run its place
    // among the block's points.
    s_.local.clear();
    s_.count.clear();
    s_.local_of_slot.resize(blocks_.size(), -1);
    for (std::size_t c = 0; c < n_chunks; ++c) {
        st.dropped_non_finite += s_.chunk_drops[c][kNonFinite - 1];
        st.dropped_at_origin += s_.chunk_drops[c][kAtOrigin - 1];
        st.dropped_range += s_.chunk_drops[c][kRange - 1];
        for (PointRun& run : s_.runs[c]) {
            if (run.slot < 0) {  // a block first seen in this scan: created once, in scan order
                run.slot = blocks_.findOrCreate(run.block);
                if (static_cast<std::size_t>(run.slot) >= s_.local_of_slot.size())
                    s_.local_of_slot.resize(static_cast<std::size_t>(run.slot) + 1, -1);
            }
            std::int32_t& l = s_.local_of_slot[static_cast<std::size_t>(run.slot)];
            if (l < 0) {
                l = static_cast<std::int32_t>(s_.local.size());
                s_.local.emplace_back();
                s_.local.back().slot = run.slot;
                s_.count.push_back(0);
            }
            run.slot = l;  // from here on: the local index
            run.offset = s_.count[static_cast<std::size_t>(l)];
            s_.count[static_cast<std::size_t>(l)] += run.length;
        }
    }
    for (const LocalBlock& b : s_.local) s_.local_of_slot[static_cast<std::size_t>(b.slot)] = -1;
}

void AtsdfIntegrator::ScanPass::scatterOrder(std::size_t n_chunks) {
    // Parallel over chunks: scatter the runs into `order` (block by block, scan order within).
    std::vector<LocalBlock>& local = s_.local;
    std::uint32_t offset = 0;
    for (std::size_t b = 0; b < local.size(); ++b) {
        local[b].begin = offset;
        offset += s_.count[b];
        local[b].end = offset;
    }
    s_.order.resize(offset);
    const bool need_local_of_point = config_.space_carving;
    if (need_local_of_point) s_.local_of_point.assign(points_W_.size(), -1);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_chunks, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c < r.end(); ++c)
            for (const PointRun& run : s_.runs[c]) {
                std::uint32_t* dst =
                    s_.order.data() + local[static_cast<std::size_t>(run.slot)].begin + run.offset;
                for (std::uint32_t k = 0; k < run.length; ++k) dst[k] = run.first + k;
                if (need_local_of_point)
                    std::fill_n(s_.local_of_point.data() + run.first, run.length, run.slot);
            }
    });
}

bool AtsdfIntegrator::ScanPass::bin(IntegrationStats& st) {
    // (a) classify in parallel, (b) number the blocks serially in scan order, (c) scatter in
    // parallel. The result is the serial scan-order binning, for any thread count.
    const std::size_t n_points = points_W_.size();
    const std::size_t n_chunks = (n_points + kPointChunk - 1) / kPointChunk;
    if (s_.runs.size() < n_chunks) s_.runs.resize(n_chunks);
    s_.chunk_drops.assign(n_chunks, {0, 0, 0});
    if (config_.merge_divisions > 0) s_.point_cell.resize(n_points);
    classifyChunks(n_chunks);
    assignLocalBlocks(n_chunks, st);
    st.points_integrated = n_points - st.dropped_non_finite - st.dropped_at_origin - st.dropped_range;
    if (s_.local.empty()) return false;
    scatterOrder(n_chunks);
    return true;
}

void AtsdfIntegrator::ScanPass::mergeStatistics() {
    // Parallel over blocks; each block touches only its own entry. The block's rays are
    // gathered here too, while its points are in the cache.
    const std::size_t n = s_.order.size();
    s_.ray_point.resize(n);
    s_.ray_count.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s_.local.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        CellRays* cells = config_.merge_divisions > 0 ? &s_.cell_rays.local() : nullptr;
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            LocalBlock& lb = s_.local[b];
            BlockEntry& entry = blocks_.entry(lb.slot);
            const BlockStats batch =
                batchStatsIndexed(points_W_.data(), s_.order.data() + lb.begin, lb.end - lb.begin);
            lb.ray_end = gatherRays(lb, cells);
            entry.stats = mergeStats(entry.stats, batch);  // paper Eq. (1)
            const PlaneEstimate plane =
                estimatePlane(entry.stats, origin_W_, config_.min_points_for_pca, min_spread_m_);
            entry.plane_valid = plane.valid;
            entry.normal_W = plane.normal.cast<float>();
            entry.flatness = static_cast<float>(plane.flatness);
            entry.truncation_m = static_cast<float>(truncationFor(trunc_, plane, entry.stats.n));
        }
    });
}

void AtsdfIntegrator::ScanPass::borrowNormals() {
    // A degenerate block borrows the n-weighted mean of the valid normals of its 26 neighbours
    // (re-oriented towards this scan's sensor); without any, its points fall back to the ray
    // direction. Neighbour entries are only read here (phase 2 is complete): deterministic.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s_.local.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false> index(blocks_.indexTree());
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            LocalBlock& lb = s_.local[b];
            const BlockEntry& entry = blocks_.entry(lb.slot);
            if (entry.plane_valid) {
                lb.normal = entry.normal_W.cast<double>();
                lb.flatness = entry.flatness;
                continue;
            }
            const Coord bc = blocks_.blockCoord(lb.slot);
            Vec3d sum = Vec3d::Zero();
            double flat_sum = 0.0, n_sum = 0.0;
            for (int dx = -1; dx <= 1; ++dx)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dz = -1; dz <= 1; ++dz) {
                        const std::int32_t nb = index.getValue(bc.offsetBy(dx, dy, dz));
                        if (nb < 0) continue;
                        const BlockEntry& ne = blocks_.entry(nb);
                        if (!ne.plane_valid) continue;
                        Vec3d n = ne.normal_W.cast<double>();
                        if (n.dot(origin_W_ - ne.stats.mean) < 0.0) n = -n;
                        sum += ne.stats.n * n;
                        flat_sum += ne.stats.n * ne.flatness;
                        n_sum += ne.stats.n;
                    }
            const double norm = sum.norm();
            lb.normal = norm > 0.0 ? Vec3d(sum / norm) : Vec3d::Zero();
            lb.flatness = n_sum > 0.0 ? static_cast<float>(flat_sum / n_sum) : 0.0f;
        }
    });
}

void AtsdfIntegrator::ScanPass::markLeaves(std::uint64_t* bits, const Coord& bc,
                                           const detail::RaySegment& seg, const Vec3f& dir) const {
    // The leaves of the box between the segment's start and end voxel, as bits of the block's
    // leaf neighbourhood (the half-length <= maxHalfLength keeps them inside it).
    const Coord c0 = seg.startVoxel();
    const Coord c1 = seg.endVoxel(dir);
    const Coord lo = BlockStatsGrid::blockOf(Coord::minComponent(c0, c1)) - bc;
    const Coord hi = BlockStatsGrid::blockOf(Coord::maxComponent(c0, c1)) - bc;
    if (lo == Coord(0) && hi == Coord(0)) {  // the common case: inside the own leaf
        const std::size_t own_bit = hood_.bit(0, 0, 0);
        bits[own_bit / 64] |= std::uint64_t{1} << (own_bit % 64);
        return;
    }
    const int R = hood_.radius;
    hood_.markBox(bits, std::max(lo.x(), -R), std::min(hi.x(), R), std::max(lo.y(), -R),
                  std::min(hi.y(), R), std::max(lo.z(), -R), std::min(hi.z(), R));
}

bool AtsdfIntegrator::ScanPass::landsOnPlane(BlockIndexAccessor& index, const Vec3f& p,
                                             const Vec3f& dir, const Vec3f& normal, float t,
                                             float band) const {
    // The band behind p may reach the next ring only where that ring lands on the same surface:
    // q, the band's end (t along the ray behind p) projected onto p's plane, must lie in a
    // block with points whose plane passes within `band` of q: the block's own plane if it has
    // one (and then of about the same normal, within ~25 deg), else p's plane through the mean
    // of its points (a block one ring crosses has no plane of its own, but its points lie on
    // the surface). Past the edge of a surface (a car's roof) the next ring hits something
    // else, and the plane is not carried on.
    const Vec3f q = p + t * (dir - normal.dot(dir) * normal);
    const std::int32_t slot = index.getValue(BlockStatsGrid::blockOf(detail::voxelOf(q, inv_vs_f_)));
    if (slot < 0) return false;
    const BlockEntry& e = blocks_.entry(slot);
    if (e.stats.n <= 0.0 || (e.plane_valid && std::abs(e.normal_W.dot(normal)) < 0.9f)) return false;
    const Vec3f& n_q = e.plane_valid ? e.normal_W : normal;
    return std::abs(n_q.dot(q - e.stats.mean.cast<float>())) <= band;
}

std::uint32_t AtsdfIntegrator::ScanPass::gatherRays(const LocalBlock& lb, CellRays* cells_or_null) const {
    // The block's rays (phase 2) into [lb.begin, returned end) of ray_point and ray_count:
    // each point, or (merge_divisions s > 0) the mean of the points of each cell (voxel / s)
    // with their count, in the order the cells are first seen. The mean is the first point
    // plus the mean offset from it, so that a cell of one point keeps it exactly.
    Vec3f* ray_point = s_.ray_point.data();
    float* ray_count = s_.ray_count.data();
    if (cells_or_null == nullptr) {  // merge_divisions 0
        for (std::uint32_t k = lb.begin; k < lb.end; ++k) {
            ray_point[k] = points_W_[s_.order[k]];
            ray_count[k] = 1.0f;
        }
        return lb.end;
    }
    CellRays& cells = *cells_or_null;
    // Each point's cell in the block (MergeCell) came from phase 1 (classifyChunk).
    std::uint32_t end = lb.begin;
    for (std::uint32_t k = lb.begin; k < lb.end; ++k) {
        const Vec3f& p = points_W_[s_.order[k]];
        const std::size_t cell = s_.point_cell[s_.order[k]];
        std::int32_t& r = cells.ray[cell];
        if (r < 0) {
            r = static_cast<std::int32_t>(end - lb.begin);
            cells.delta_sum[static_cast<std::size_t>(r)].setZero();
            cells.used[cells.n_used++] = static_cast<std::uint32_t>(cell);
            ray_point[end] = p;
            ray_count[end] = 1.0f;
            ++end;
        } else {
            const std::uint32_t i = lb.begin + static_cast<std::uint32_t>(r);
            cells.delta_sum[static_cast<std::size_t>(r)] += p - ray_point[i];
            ray_count[i] += 1.0f;
        }
    }
    for (std::uint32_t i = lb.begin; i < end; ++i)
        if (ray_count[i] > 1.0f) ray_point[i] += cells.delta_sum[i - lb.begin] / ray_count[i];
    for (std::size_t u = 0; u < cells.n_used; ++u) cells.ray[cells.used[u]] = -1;
    cells.n_used = 0;
    return end;
}

void AtsdfIntegrator::ScanPass::planSegments() {
    // Parallel over blocks: each ray's direction, update segment (kept for phase 3) and the
    // leaves it crosses. The segment along the ray is rayBandFor (Truncation.h): [-eps, eps]
    // in the paper and fixed modes; in the adaptive mode a band of at least b across the
    // surface, widened in front of the point up to L_max, behind max(eps, b) along the ray but
    // no deeper than b across the surface.
    const std::size_t n = s_.order.size();
    s_.leaf_bits.assign(s_.local.size() * hood_.words, 0);
    s_.dir.resize(n);
    s_.segment.resize(n);
    const bool along_normal = trunc_.mode == TruncationMode::Adaptive;
    // L_max >= eps_max >= eps (validateTruncation).
    const float l_max = static_cast<float>(maxAlongRay(trunc_));
    const float band = static_cast<float>(trunc_.grazing_band_m);
    const bool both_sides = trunc_.grazing_band_both_sides;
    const RingSpacing* rings = s_.use_rings ? &s_.rings : nullptr;
    // Each step is its own loop over the block's rays: a step's square root and divisions are
    // long-latency operations, and in a short loop body the processor overlaps those of
    // successive rays (one loop doing all steps per ray waited on each in turn).
    s_.plan.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s_.local.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        BlockIndexAccessor index(blocks_.indexTree());
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            const LocalBlock& lb = s_.local[b];
            const float eps = blocks_.entry(lb.slot).truncation_m;
            const bool has_normal = along_normal && lb.normal.squaredNorm() > 0.0;
            const Vec3f normal = lb.normal.cast<float>();
            RayPlan* plan = s_.plan.data();
            // (a) Direction and range.
            for (std::uint32_t k = lb.begin; k < lb.ray_end; ++k) {
                const Vec3f ray = s_.ray_point[k] - origin_f_;
                const float range = std::sqrt(ray.squaredNorm());
                s_.dir[k] = ray * (1.0f / range);  // one division
                plan[k].range_m = range;
            }
            // (b) The band along the ray: rayBandFor (Truncation.h), in float.
            if (has_normal) {
                for (std::uint32_t k = lb.begin; k < lb.ray_end; ++k) {
                    const float c = std::abs(normal.dot(s_.dir[k]));
                    plan[k].band = adaptiveBand(eps, c, band, l_max, both_sides);
                }
            } else {
                for (std::uint32_t k = lb.begin; k < lb.ray_end; ++k) plan[k].band = {eps, eps, eps};
            }
            // (c) Reach the next ring, if it lands on this surface (AdaptiveBand::backToRing).
            // Where the reach is no longer than the band already is (frontal points) the gap
            // cannot matter.
            if (has_normal && rings != nullptr) {
                for (std::uint32_t k = lb.begin; k < lb.ray_end; ++k) {
                    AdaptiveBand<float>& ab = plan[k].band;
                    if (!(ab.reach_m > ab.back_m)) continue;
                    const Vec3f& dir = s_.dir[k];
                    const float to_ring =
                        ab.backToRing(rings->surfaceGap(dir, normal, s_.up_W, plan[k].range_m));
                    if (to_ring > ab.back_m &&
                        landsOnPlane(index, s_.ray_point[k], dir, normal, to_ring, band))
                        ab.back_m = to_ring;
                }
            }
            // (d) The segment and the leaves it crosses. A merged ray's band starts further in
            // front (mergedRayFrontExtension).
            const Coord bc = blocks_.blockCoord(lb.slot);
            std::uint64_t* bits = s_.leaf_bits.data() + b * hood_.words;
            for (std::uint32_t k = lb.begin; k < lb.ray_end; ++k) {
                const float front = plan[k].band.front_m + (s_.ray_count[k] > 1.0f ? merged_front_m_ : 0.0f);
                const detail::RaySegment seg = detail::RaySegment::of(
                    s_.ray_point[k], s_.dir[k], front, plan[k].band.back_m, inv_vs_f_);
                s_.segment[k] = seg;
                markLeaves(bits, bc, seg, s_.dir[k]);
            }
        }
    });
}

void AtsdfIntegrator::ScanPass::allocate(IntegrationStats& st) {
    // Find the leaves that do not exist yet (parallel, read-only), then allocate them (serial:
    // tree topology changes are not thread-safe).
    TsdfTree& tsdf_tree = map_.workingTsdf()->tree();
    const std::vector<LocalBlock>& local = s_.local;
    s_.missing_bits.assign(s_.leaf_bits.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, local.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        openvdb::tree::ValueAccessor<const TsdfTree, false> acc(tsdf_tree);
        for (std::size_t b = r.begin(); b < r.end(); ++b) {
            const Coord bc = blocks_.blockCoord(local[b].slot);
            const std::uint64_t* bits = s_.leaf_bits.data() + b * hood_.words;
            std::uint64_t* missing = s_.missing_bits.data() + b * hood_.words;
            forEachSetBit(bits, hood_.words, [&](std::size_t bit) {
                if (acc.probeConstLeaf(hood_.origin(bc, bit)) == nullptr)
                    missing[bit / 64] |= std::uint64_t{1} << (bit % 64);
            });
        }
    });
    // A missing leaf is new, or in the compact store: then its values come back from it.
    std::vector<TsdfLeaf*>& created = s_.created;
    created.clear();
    openvdb::tree::ValueAccessor<TsdfTree> acc(tsdf_tree);
    for (std::size_t b = 0; b < local.size(); ++b) {
        const Coord bc = blocks_.blockCoord(local[b].slot);
        forEachSetBit(s_.missing_bits.data() + b * hood_.words, hood_.words, [&](std::size_t bit) {
            const Coord origin = hood_.origin(bc, bit);
            if (acc.probeConstLeaf(origin) == nullptr) created.push_back(acc.touchLeaf(origin));
        });
    }
    if (map_.compactTsdf().leafCount() > 0) st.leaves_reloaded = map_.reloadIntoWorking(created);
}

std::size_t AtsdfIntegrator::ScanPass::integrateCell(std::size_t cell_index,
                                                     detail::BlockLeafTable& table,
                                                     detail::TsdfLeafCache::Accessor& acc) const {
    // The voxel updates of one cell go straight into the packed leaves of each block's
    // neighbourhood (`table`, one per task). Returns the number of updates.
    const bool paper_weight = trunc_.mode == TruncationMode::Paper;
    const float floor_w = static_cast<float>(config_.weight_floor);
    const float q = static_cast<float>(config_.noise_ratio);
    const float vs_f = static_cast<float>(vs_);
    detail::RayWeight weight;
    if (!paper_weight && config_.falloff_m > 0.0) {
        weight.inv_falloff2 = static_cast<float>(1.0 / (config_.falloff_m * config_.falloff_m));
        weight.falloff_floor = floor_w;
    }
    std::size_t updates = 0;
    for (std::uint32_t i = s_.cell_begin[cell_index]; i < s_.cell_begin[cell_index + 1]; ++i) {
        const std::uint32_t b = s_.by_cell[i];
        const LocalBlock& lb = s_.local[b];
        const float eps = blocks_.entry(lb.slot).truncation_m;
        weight.inv_dropoff = eps > vs_f ? 1.0f / (eps - vs_f) : 0.0f;
        // No normal (isolated degenerate block): the ray direction (sdf along the ray).
        const bool has_normal = lb.normal.squaredNorm() > 0.0;
        const Vec3f block_normal = lb.normal.cast<float>();
        const float q_block = blockNoiseRatio(q, lb.flatness);  // per block, not per point
        table.load(blocks_.blockCoord(lb.slot), s_.leaf_bits.data() + b * hood_.words, acc, stamp_);
        for (std::uint32_t k = lb.begin; k < lb.ray_end; ++k) {
            const Vec3f& p = s_.ray_point[k];
            const Vec3f& dir = s_.dir[k];
            const Vec3f normal = has_normal ? block_normal : Vec3f(-dir);
            if (paper_weight) {
                weight.w_inc = has_normal ? incidenceWeightAlongRay(normal, dir, floor_w) : 1.0f;
            } else {
                weight.w_inc = noiseWeight(std::abs(normal.dot(dir)), q_block);
            }
            weight.w_inc *= s_.ray_count[k];  // a merged ray counts as its points
            updates += detail::integrateRay(s_.segment[k], p, dir, normal, eps, vs_f, weight, table);
        }
    }
    return updates;
}

void AtsdfIntegrator::ScanPass::integrate(IntegrationStats& st) {
    // Colour the blocks by cell (2 neighbourhood radii wide), then run the colours one after
    // another, the cells of one colour in parallel (CellColouring.h).
    std::vector<LocalBlock>& local = s_.local;
    const int cell_blocks = 2 * hood_.radius;
    for (LocalBlock& lb : local) lb.cell = detail::cellKeyOf(blocks_.blockCoord(lb.slot), cell_blocks);
    // The blocks by (cell key, block): sorted as plain numbers, not through `local`.
    std::vector<std::pair<std::uint64_t, std::uint32_t>>& keyed = s_.keyed_blocks;
    keyed.resize(local.size());
    for (std::size_t b = 0; b < local.size(); ++b)
        keyed[b] = {local[b].cell.packed(), static_cast<std::uint32_t>(b)};
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t>& by_cell = s_.by_cell;
    by_cell.resize(local.size());
    // Cell ranges within by_cell.
    std::vector<std::uint32_t>& cell_begin = s_.cell_begin;
    cell_begin.clear();
    for (std::size_t i = 0; i < keyed.size(); ++i) {
        by_cell[i] = keyed[i].second;
        if (i == 0 || keyed[i].first != keyed[i - 1].first) cell_begin.push_back(static_cast<std::uint32_t>(i));
    }
    cell_begin.push_back(static_cast<std::uint32_t>(by_cell.size()));

    TsdfTree& tsdf_tree = map_.workingTsdf()->tree();
    const TsdfCodec& codec = map_.codec();
    const float max_weight = static_cast<float>(config_.max_weight);
    const std::size_t num_cells = cell_begin.size() - 1;
    s_.updates_per_cell.assign(num_cells, 0);
    std::size_t colour_start = 0;
    while (colour_start < num_cells) {
        const std::uint32_t colour = local[by_cell[cell_begin[colour_start]]].cell.colour;
        std::size_t colour_end = colour_start;
        while (colour_end < num_cells && local[by_cell[cell_begin[colour_end]]].cell.colour == colour)
            ++colour_end;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(colour_start, colour_end, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              detail::TsdfLeafCache::Accessor acc(tsdf_tree);
                              detail::BlockLeafTable table(hood_, codec, max_weight);
                              for (std::size_t c = r.begin(); c < r.end(); ++c)
                                  s_.updates_per_cell[c] = integrateCell(c, table, acc);
                          });
        colour_start = colour_end;
    }
    for (std::size_t u : s_.updates_per_cell) st.voxel_updates += u;
    for (const LocalBlock& lb : local) st.rays += lb.ray_end - lb.begin;
}

void AtsdfIntegrator::ScanPass::carve(IntegrationStats& st) {
    // Serial, deterministic: along the ray from the sensor to (point - eps), voxels already
    // observed are updated with sdf = +eps_max (free space). Never allocates.
    TsdfTree& tsdf_tree = map_.workingTsdf()->tree();
    const TsdfCodec& codec = map_.codec();
    const float max_weight = static_cast<float>(config_.max_weight);
    const double inv_vs = 1.0 / vs_;
    detail::TsdfLeafCache::Accessor acc(tsdf_tree);
    detail::TsdfLeafCache cache(codec);
    CompactTsdf& compact = map_.compactTsdf();
    openvdb::tree::ValueAccessor<const CompactTsdf::TopologyTree, false> compact_acc(compact.topology());
    const float free_sdf = static_cast<float>(trunc_.max_m);
    for (std::size_t i = 0; i < points_W_.size(); ++i) {
        const std::int32_t l = s_.local_of_point[i];
        if (l < 0) continue;
        const double eps = blocks_.entry(s_.local[static_cast<std::size_t>(l)].slot).truncation_m;
        const Vec3d p = points_W_[i].cast<double>();
        const Vec3d ray = p - origin_W_;
        const double range = ray.norm();
        if (range <= eps) continue;
        detail::traverseSegment(origin_W_, ray / range, range - eps - vs_, inv_vs, [&](const Coord& v) {
            if (cache.fetch(v, acc)) {
                if (cache.updateObserved(v, free_sdf, 1.0f, max_weight)) ++st.carving_updates;
            } else if (std::uint32_t* value = compact.findObserved(v, compact_acc)) {
                detail::observedAverage(*value, free_sdf, 1.0f, max_weight, codec);
                ++st.carving_updates;
            }
        });
    }
}

void AtsdfIntegrator::ScanPass::retire(IntegrationStats& st) {
    // Every leaf a block's updates can reach was stamped with this scan (BlockLeafTable::load);
    // those no scan of the working set could update go to the compact store.
    const std::uint32_t keep = static_cast<std::uint32_t>(config_.working_set_scans);
    if (stamp_ >= keep) st.leaves_retired = map_.retireWorking(stamp_ - keep + 1);
}

IntegrationStats AtsdfIntegrator::integrateScan(const std::vector<Vec3f>& points_W,
                                                const Vec3d& origin_W) {
    scratch_->use_rings = false;  // no sensor frame: the rings are unknown
    return integrateInWorld(points_W, origin_W);
}

IntegrationStats AtsdfIntegrator::integrateInWorld(const std::vector<Vec3f>& points_W,
                                                   const Vec3d& origin_W) {
    IntegrationStats st;
    st.scans = 1;
    st.points_in = points_W.size();
    if (points_W.empty() || !origin_W.allFinite()) {
        st.dropped_non_finite = origin_W.allFinite() ? 0 : points_W.size();
        totals_ += st;
        return st;
    }
    ScanPass pass(map_, config_, *scratch_, points_W, origin_W,
                  static_cast<std::uint32_t>(totals_.scans + 1));
    auto t0 = Clock::now();
    auto lap = [&t0]() {
        const double s = secondsSince(t0);
        t0 = Clock::now();
        return s;
    };
    const bool any = pass.bin(st);
    st.bin_s = lap();
    if (!any) {
        totals_ += st;
        return st;
    }
    pass.mergeStatistics();
    pass.borrowNormals();
    pass.planSegments();
    st.stats_s = lap();
    pass.allocate(st);
    st.alloc_s = lap();
    pass.integrate(st);
    if (config_.space_carving) pass.carve(st);
    st.update_s = lap();
    pass.retire(st);
    st.retire_s = lap();
    totals_ += st;
    return st;
}

void AtsdfIntegrator::describeMap() {
    // The settings the map was made with; set from the start, so that a tile's own map.vdb,
    // written while the scans still come in (tiling.map_vdb: per_tile), carries them too.
    openvdb::MetaMap& meta = map_.metadata();
    meta.insertMeta("voxel_size_m", openvdb::DoubleMetadata(map_.voxelSize()));
    meta.insertMeta("truncation_mode",
                    openvdb::StringMetadata(truncationModeName(config_.truncation.mode)));
    meta.insertMeta("truncation_min_m", openvdb::DoubleMetadata(config_.truncation.min_m));
    meta.insertMeta("truncation_max_m", openvdb::DoubleMetadata(config_.truncation.max_m));
    meta.insertMeta("truncation_max_along_ray_m",
                    openvdb::DoubleMetadata(maxAlongRay(config_.truncation)));
    meta.insertMeta("grazing_band_m", openvdb::DoubleMetadata(config_.truncation.grazing_band_m));
    meta.insertMeta("flatness_k", openvdb::DoubleMetadata(config_.truncation.flatness_k));
    meta.insertMeta("reference_points", openvdb::DoubleMetadata(config_.truncation.reference_points));
    meta.insertMeta("weight_floor", openvdb::DoubleMetadata(config_.weight_floor));
    meta.insertMeta("range_noise_m", openvdb::DoubleMetadata(config_.range_noise_m));
    meta.insertMeta("noise_ratio", openvdb::DoubleMetadata(config_.noise_ratio));
    meta.insertMeta("falloff_m", openvdb::DoubleMetadata(config_.falloff_m));
    meta.insertMeta("max_weight", openvdb::DoubleMetadata(config_.max_weight));
    meta.insertMeta("space_carving", openvdb::BoolMetadata(config_.space_carving));
}

void AtsdfIntegrator::finalize() {
    map_.compact();
    // The per-voxel truncation grid is derived from the block statistics when map.vdb is
    // written (VoxelMap::truncationGrid), so it costs no memory while the map is in use.
    describeMap();
    map_.metadata().insertMeta("scans_integrated",
                               openvdb::Int64Metadata(static_cast<std::int64_t>(totals_.scans)));
}

}  // namespace vdbmap
