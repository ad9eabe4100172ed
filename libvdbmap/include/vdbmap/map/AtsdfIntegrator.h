// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/map/RingSpacing.h"
#include "vdbmap/map/Truncation.h"

namespace vdbmap {

class VoxelMap;

/// merge_divisions of AtsdfConfig: 1 (voxel) in the adaptive mode, 0 (none) in the others.
inline constexpr int kMergeAuto = -1;

/// Settings of the adaptive TSDF integration (paper Sec. 4). The defaults are the product's,
/// the one source of them: the integrate.atsdf stage binds its options to these fields (and
/// tests/unit/AtsdfStageDefaultsTest.cpp checks that its defaults equal them), so a library
/// caller with AtsdfConfig{} builds what `vdbmap run` builds. Lengths in voxels resolve
/// against the map's voxel size (resolveAtsdfConfig; AtsdfIntegrator does it).
struct AtsdfConfig {
    TruncationParams truncation;
    int min_points_for_pca = 5;     ///< blocks with fewer points are degenerate
    /// Lower bound, in (0, 1], of the paper's incidence weight (paper mode) and of the distance
    /// falloff (adaptive and fixed modes).
    double weight_floor = 0.1;
    /// Cap of the accumulated weight per voxel (a frontal sample weighs 1, a grazing one up to
    /// 1 + noise_ratio^2). The map's weight range must hold it (makeVoxelMap).
    double max_weight = 1000.0;
    /// sigma_r, the sensor's 1-sigma range noise (m). A block whose points spread less than
    /// 2 sigma_r across their main direction is degenerate: one ring's points with range noise
    /// form a ribbon spanned by the ring and the rays themselves, whose "normal" is
    /// perpendicular to the rays (estimatePlane's min_spread_m = max(0.25 voxel, 2 sigma_r)).
    double range_noise_m = 0.02;
    /// q = sigma_r / sigma_0 of noiseWeight (adaptive and fixed modes; vdbmap/map/
    /// MeasurementWeight.h): a grazing sample counts up to 1 + q^2 times a frontal one.
    double noise_ratio = 3.0;
    /// l of distanceFalloff (adaptive and fixed modes) in voxels, used when falloff_m is 0.
    double falloff_voxels = 1.0;
    /// l of distanceFalloff in metres; 0 = falloff_voxels voxels (both 0: no falloff).
    double falloff_m = 0.0;
    /// Space carving: along the ray from the sensor to (point - eps), voxels that are already
    /// allocated are updated with sdf = +eps_max (free space). Never allocates free space.
    bool space_carving = false;
    /// 0: every point walks its own ray. 1 (2): the points of a scan that fall in one voxel (in
    /// one cell of half a voxel's side) update the map as one ray: their mean, with their count
    /// as weight. Exact where their rays cross the same voxels with the same weights (the sdf
    /// n . (c - p) is linear in p, one normal per block); near the sensor, where a voxel holds
    /// many points, it saves most of the ray walks. The band of a ray that stands for two or
    /// more points starts further in front of their mean, by mergedRayFrontExtension.
    /// kMergeAuto: 1 in the adaptive mode (its band keeps b across every surface), 0 in the
    /// fixed and paper modes (their band can be a voxel thin across a grazing surface, and
    /// fewer rays would leave holes there).
    int merge_divisions = kMergeAuto;
    double min_range_m = 1e-3;      ///< closer to the sensor: dropped as "at origin"
    double max_range_m = 1000.0;    ///< further: dropped as absurd range
    /// A leaf stays dense in the map's working tree while one of the last `working_set_scans`
    /// scans could update it; then it moves to the compact store (VoxelMap), and back when a
    /// later scan reaches it again. Lossless: the map does not depend on it, only the memory
    /// (small: fewer dense leaves) and the time spent moving leaves (small: less churn).
    int working_set_scans = 4;
};

/// `config` as the integrator runs it at `voxel_size_m`: the truncation resolved
/// (resolveTruncation), falloff_m from falloff_voxels where 0, kMergeAuto replaced by 0 or 1.
/// A resolved config resolves to itself.
AtsdfConfig resolveAtsdfConfig(const AtsdfConfig& config, double voxel_size_m);

/// Checks `config` at `voxel_size_m`: its voxel counts, then the resolved values. Throws
/// ConfigError naming the bad key (the integrate.atsdf option) and value, prefixed by `who`.
void validateAtsdfConfig(const AtsdfConfig& config, double voxel_size_m, const std::string& who);

/// "auto", "none", "voxel", "half_voxel" (the stage's merge_points) for merge_divisions
/// kMergeAuto, 0, 1, 2; and back. parseMergePoints throws ConfigError naming the bad value.
const char* mergePointsName(int merge_divisions);
int parseMergePoints(const std::string& text);

/// A map for `config` at `voxel_size_m`, as integrate.atsdf makes it: its sdf range (and
/// background) the resolved eps_max, its weight range max_weight. Throws as VoxelMap does.
std::shared_ptr<VoxelMap> makeVoxelMap(const AtsdfConfig& config, double voxel_size_m);

/// How much further in front of its mean (towards the sensor) the band of a merged ray starts
/// than a point's: half the diagonal of its cell, sqrt(3) / 2 * voxel / merge_divisions
/// (resolved); 0 without merging. One ray loses some of the voxels that the separate rays of its points
/// covered at the ends of their bands: on a real KITTI scan merged rays left more of the ground
/// empty and were less accurate there than fixed eps_max at [0.1, 0.3] m. With this extension
/// they are not, and every simulated target holds (docs/results/geometry.md, "Merged rays with
/// a longer front"). It is a measured remedy, not the points' own extent: extending by the
/// points' spread along the ray alone did not recover the real scan.
double mergedRayFrontExtension(const AtsdfConfig& config, double voxel_size_m);

/// The furthest an update lands from its point (m): maxHalfLength of the resolved truncation
/// plus mergedRayFrontExtension.
double maxUpdateReach(const AtsdfConfig& config, double voxel_size_m);

/// Counts of one or more integrated scans.
struct IntegrationStats {
    std::size_t scans = 0;
    std::size_t points_in = 0;
    std::size_t points_integrated = 0;
    std::size_t dropped_non_finite = 0;
    std::size_t dropped_at_origin = 0;
    std::size_t dropped_range = 0;
    std::size_t rays = 0;  ///< rays walked: points_integrated, or fewer with merge_divisions
    std::size_t voxel_updates = 0;
    std::size_t carving_updates = 0;
    std::size_t leaves_reloaded = 0;  ///< compact leaves moved back into the working tree
    std::size_t leaves_retired = 0;   ///< working leaves moved to the compact store
    /// Wall time of the phases (seconds, summed over scans): classify and bin the points;
    /// merge the block statistics and derive plane, eps and the leaves to touch; allocate
    /// missing leaves (or reload them from the compact store); the voxel updates (and space
    /// carving); move the leaves that left the working set to the compact store.
    double bin_s = 0.0;
    double stats_s = 0.0;
    double alloc_s = 0.0;
    double update_s = 0.0;
    double retire_s = 0.0;

    IntegrationStats& operator+=(const IntegrationStats& other);
};

/// Adaptive TSDF integration into a VoxelMap (paper Sec. 4, on OpenVDB).
///
/// Per scan (each phase a function of AtsdfIntegrator.cpp's ScanPass):
///  1. bin: points are checked (non-finite, at the origin, absurd range: counted and skipped)
///     and binned by 8^3 block in scan order;
///  2. mergeStatistics: each block's batch statistics (batchStatsIndexed) are merged into its
///     BlockEntry (paper Eq. (1)), then its plane (Eq. (2), (3)) and eps (Eq. (4)) are
///     recomputed: a point uses the eps of its own block AFTER the current scan's merge;
///     gatherRays: the block's rays, each point or (merge_divisions) one per cell of its
///     points, their mean weighted by their count;
///     borrowNormals: the normal used for a block's points is its own plane's; a degenerate
///     block borrows the n-weighted mean of its 26 neighbours' valid normals (re-oriented
///     towards the sensor), and only without any valid neighbour falls back to the ray
///     direction (sdf along the ray, incidence weight 1);
///     planSegments: each ray's segment, t in [-front, back] around the point
///     (rayBandFor, Truncation.h): [-eps, eps] in the paper and fixed modes; in the adaptive
///     mode at least b = grazing_band_m across the surface (b / |n . d| along the ray, in front
///     up to L_max, behind max(eps, b) but at most b across the surface);
///  3. allocate the leaves the segments cross; integrate: every voxel v the segment pierces
///     (DDA) gets sdf = n . (v - p) (the distance to the block's plane), clamped to
///     [-eps, eps], with weight w = noiseWeight(|n . d|) * distanceFalloff(t) *
///     behindSurfaceFactor (adaptive, fixed; t: the voxel's distance along the ray from p) or
///     the paper's incidenceWeight * behindSurfaceFactor (paper mode), and the running
///     average D' = (W D + w d) / (W + w), W' = min(W + w, max_weight); carve (optional);
///  4. retire: the leaves no scan of the last `working_set_scans` could update move to the
///     map's compact store (VoxelMap).
///
/// Parallel (TBB) and deterministic: phases 1 and 2 are parallel over points / blocks; phase 3
/// groups blocks into cells twice as wide as the update reach (map/CellColouring.h) and runs the
/// 8 colour classes (cell coordinate mod 2) one after another, cells of one colour in parallel.
/// Cells of one colour never write the same voxel, and each voxel sees its updates in a fixed
/// order (colour, cell, then block order of first appearance, then ray order): the result does not
/// depend on the thread count. No atomics, no locks in the voxel loop.
class AtsdfIntegrator {
public:
    /// Runs resolveAtsdfConfig(config, map.voxelSize()). Throws ConfigError on a bad config, or
    /// if truncation max or max weight exceed the map's sdf or weight range (VoxelMap's
    /// constructor; best: the sdf range = truncation max, as makeVoxelMap makes it).
    AtsdfIntegrator(VoxelMap& map, const AtsdfConfig& config);
    ~AtsdfIntegrator();
    AtsdfIntegrator(const AtsdfIntegrator&) = delete;
    AtsdfIntegrator& operator=(const AtsdfIntegrator&) = delete;

    /// Integrates one scan given in the world frame, observed from `origin_W`. Empty scans are
    /// a no-op (counted). Never throws on bad points (they are counted in the stats).
    IntegrationStats integrateScan(const std::vector<Vec3f>& points_W, const Vec3d& origin_W);
    /// Same with points in the LiDAR frame and the pose T_W_L.
    IntegrationStats integrateScan(PointSpan points_L, const Isometry3d& T_W_L);
    /// Same with the scan's rings estimated already (RingSpacing::estimate(points_L)), e.g. by
    /// the reader of the scan while the scan before was integrated.
    IntegrationStats integrateScan(PointSpan points_L, const Isometry3d& T_W_L,
                                   const RingSpacing& rings);
    /// True if integrateScan in the LiDAR frame uses the scan's rings (the adaptive mode's
    /// grazing_band_to_next_ring).
    bool usesRings() const;

    /// Writes the truncation settings into the map's metadata (map.vdb then also gets the
    /// per-voxel "truncation" grid, VoxelMap::truncationGrid) and moves every leaf to the
    /// compact store, dropping leaves without active voxels. Call after the last scan.
    void finalize();

    /// The config as run: resolved at the map's voxel size.
    const AtsdfConfig& config() const { return config_; }
    const IntegrationStats& totals() const { return totals_; }

private:
    /// The map's metadata of the settings (all of finalize()'s but scans_integrated); set
    /// from the start, so that a tile's own map.vdb written mid-run carries them.
    void describeMap();
    VoxelMap& map_;
    AtsdfConfig config_;
    IntegrationStats totals_;
    struct Scratch;
    class ScanPass;  ///< one scan's phases (AtsdfIntegrator.cpp)
    /// Both integrateScan overloads: the scan's rings (Scratch) are set or cleared first.
    IntegrationStats integrateInWorld(const std::vector<Vec3f>& points_W, const Vec3d& origin_W);
    /// Per-scan buffers, reused across scans (no allocation or page faults in steady state).
    std::unique_ptr<Scratch> scratch_;
};

}  // namespace vdbmap
