// SPDX-License-Identifier: Apache-2.0
#include "stages/TsdfStages.h"
#include "stages/DynamicRemovalStep.h"
#include "stages/KeepPoints.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <utility>

#include "pipeline/ContextBuilder.h"
#include "pipeline/PointRegion.h"
#include "pipeline/ScanStream.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/BlockStats.h"
#include "vdbmap/map/IntegrateDataset.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/map/VoxelSize.h"
#include "vdbmap/mesh/MarchingCubes.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/StageRegistry.h"
#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap::detail {
namespace {

/// In a process of a distributed run, the filter that drops the points outside the ground its
/// tiles need (issue 37; none with space carving, whose rays change voxels all the way from
/// the sensor); empty otherwise. It runs after the scan's rings are estimated (the late filter
/// of integrateDataset), so that the points it keeps are integrated as in a single process.
/// `dropped` counts them; it is read once the scans are done.
ScanFilter pointRegionFilter(const Dataset& dataset, const PointRegion* region, std::size_t& dropped) {
    if (!region) return {};
    return [&dataset, region, &dropped](std::size_t frame, PointCloud& cloud,
                                        const std::vector<std::uint32_t>&, std::size_t) {
        const Isometry3d& T_W_L = dataset.frame(frame).T_W_L;
        const Eigen::Matrix3f R = T_W_L.linear().cast<float>();
        const Vec3f t = T_W_L.translation().cast<float>();
        const std::size_t before = cloud.points.size();
        keepPoints(cloud, [&](std::size_t i) { return region->contains(R * cloud.points[i] + t); });
        dropped += before - cloud.points.size();
    };
}

/// integrate.atsdf: adaptive TSDF integration of every scan of the dataset (paper Sec. 4).
class IntegrateAtsdfStage : public Stage {
public:
    std::string_view name() const override { return "integrate.atsdf"; }
    std::string_view summary() const override {
        return "Adaptive-truncation TSDF integration of the LiDAR scans into OpenVDB grids";
    }
    /// Every option is bound to a field of AtsdfConfig (or, for the two enumerations, a string
    /// parsed into one) with that field's default: the struct is the one source of the
    /// defaults (kiss-icp's KISSConfig), so the library and `vdbmap run` build the same
    /// integrator (tests/unit/AtsdfStageDefaultsTest.cpp).
    void declareOptions(OptionSpec& spec) override {
        const AtsdfConfig d;
        const TruncationParams& dt = d.truncation;
        TruncationParams& t = config_.truncation;
        spec.add("voxel_size_m", "Edge length of a voxel", voxel_size_m_, kDefaultVoxelSizeM, "m");
        spec.add("truncation_mode",
                 "adaptive (eps of paper Eq. 4 per 8^3 block; the band keeps b = grazing_band_voxels "
                 "across grazing surfaces: along the ray min(max(eps, b / |n.d|), L_max) in front of "
                 "the point, min(max(eps, b), b / |n.d|) behind it; samples weighted by noise_ratio "
                 "and falloff_voxels), paper (Eq. 4, [-eps, eps] along the ray, the paper's incidence "
                 "weight) or fixed (= truncation_max_m along the ray, the adaptive mode's weights)",
                 truncation_mode_, std::string(truncationModeName(dt.mode)));
        spec.add("truncation_min_voxels",
                 "eps_min in voxels (used when truncation_min_m is 0): the truncation of densely "
                 "sampled or non-flat blocks, i.e. the detail. 4 = the paper's streets (0.40 m at "
                 "0.10 m voxels) and SUV (0.10 m at 0.025 m)",
                 t.min_voxels, dt.min_voxels, "voxels");
        spec.add("truncation_max_voxels",
                 "eps_max in voxels (used when truncation_max_m is 0): the truncation of sparse, "
                 "flat blocks and the farthest reach of a grazing ray, i.e. what closes the gaps "
                 "between LiDAR rings. 8 = the paper's streets (0.80 m at 0.10 m voxels); 12 = its "
                 "SUV, a close object (0.30 m at 0.025 m)",
                 t.max_voxels, dt.max_voxels, "voxels");
        spec.add("truncation_min_m", "Lower bound eps_min of the truncation distance (0 = truncation_min_voxels)",
                 t.min_m, dt.min_m, "m");
        spec.add("truncation_max_m",
                 "Upper bound eps_max of the truncation, the fixed value in fixed mode (0 = "
                 "truncation_max_voxels)",
                 t.max_m, dt.max_m, "m");
        spec.add("truncation_max_along_ray_m",
                 "Adaptive mode: L_max, the cap of an update's half-length along a grazing ray (0 = "
                 "eps_max)",
                 t.max_along_ray_m, dt.max_along_ray_m, "m");
        spec.add("grazing_band_voxels",
                 "Adaptive mode: b, the least half-width of the band across a surface (along its "
                 "normal) in voxels; a grazing ray's update reaches b / |n.d| along it",
                 t.grazing_band_voxels, dt.grazing_band_voxels, "voxels");
        spec.add("grazing_band_both_sides",
                 "Adaptive mode: behind the point too, the band reaches b across the surface "
                 "(min(b / |n.d|, L_max) along the ray) instead of min(max(eps, b), b / |n.d|)",
                 t.grazing_band_both_sides, dt.grazing_band_both_sides);
        spec.add("grazing_band_to_next_ring",
                 "Adaptive mode: behind a grazing point the band reaches the next ring of the scan "
                 "(g = r sin(e dtheta) / sin(alpha - e dtheta), rings found in each scan), up to "
                 "min(b / |n.d|, L_max), where that ring lands on the same plane; off: "
                 "min(max(eps, b), b / |n.d|)",
                 t.grazing_band_to_next_ring, dt.grazing_band_to_next_ring);
        spec.add("flatness_k", "Weight k of the flatness in eps = k P_flat n_ref / n eps_max",
                 t.flatness_k, dt.flatness_k);
        spec.add("reference_density_pts_m2",
                 "Surface density giving n_ref = density * (8 voxel)^2, the points per block at which a "
                 "flat block gets k * eps_max (n enters Eq. 4 as n / n_ref)",
                 t.reference_density_pts_m2, dt.reference_density_pts_m2, "1/m^2");
        spec.add("reference_points",
                 "n_ref given directly (points per block); 0 = from reference_density_pts_m2",
                 t.reference_points, dt.reference_points);
        spec.add("min_points_for_pca", "Blocks with fewer points are degenerate (eps_max, ray normal)",
                 config_.min_points_for_pca, d.min_points_for_pca);
        spec.add("weight_floor",
                 "Lower bound, in (0, 1], of the paper's incidence weight (paper mode) and of the "
                 "distance falloff (adaptive, fixed)",
                 config_.weight_floor, d.weight_floor);
        spec.add("max_weight",
                 "Cap of the accumulated weight per voxel (a frontal sample weighs 1, a grazing one "
                 "up to 1 + noise_ratio^2)",
                 config_.max_weight, d.max_weight);
        spec.add("range_noise_m",
                 "1-sigma range noise of the sensor: a block whose points spread less than twice "
                 "this across their main direction (one ring: a ribbon along the rays) gets no normal",
                 config_.range_noise_m, d.range_noise_m, "m");
        spec.add("noise_ratio",
                 "Adaptive, fixed: q = range noise / noise floor of a sample's distance along the "
                 "normal; a sample at incidence cosine c weighs (1 + q^2) / (1 + q^2 c^2) (0 = 1)",
                 config_.noise_ratio, d.noise_ratio);
        spec.add("falloff_voxels",
                 "Adaptive, fixed: l in voxels; a sample counts 1 / (1 + (t / l)^2) (at least "
                 "weight_floor) at a voxel t along the ray from its point (0 = no falloff)",
                 config_.falloff_voxels, d.falloff_voxels, "voxels");
        spec.add("merge_points",
                 "auto, none, voxel or half_voxel: the points of a scan in one voxel (in one cell of "
                 "half a voxel's side) update the map as one ray, their mean weighted by their count "
                 "(the sdf n.(c - p) is linear in p; only the voxels their rays cross and the "
                 "weights along them can differ; a merged ray's band starts half a cell diagonal "
                 "further in front, which keeps the ground the separate rays covered); near the "
                 "sensor most ray walks are saved. auto: voxel in the adaptive mode, whose band "
                 "keeps b across every "
                 "surface; none in the fixed and paper modes, whose band can be a voxel thin across "
                 "a grazing surface (fewer rays would leave holes there)",
                 merge_points_, std::string(mergePointsName(d.merge_divisions)));
        spec.add("space_carving",
                 "Push already allocated voxels in front of the band towards free space (+eps_max)",
                 config_.space_carving, d.space_carving);
        spec.add("working_set_scans",
                 "Scans a leaf stays dense after the last scan that could update it; then it moves "
                 "to the compact store (lossless: only memory and time depend on it)",
                 config_.working_set_scans, d.working_set_scans);
        declareDynamicOptions(spec, dynamic_);
    }
    void initialize() override {
        if (!(voxel_size_m_ >= kMinVoxelSizeM) || !std::isfinite(voxel_size_m_)) {
            std::ostringstream os;
            os << "option 'voxel_size_m' must be finite and >= " << kMinVoxelSizeM
               << " (the smallest accepted voxel, 1 mm), got " << voxel_size_m_;
            failConfig(os.str());
        }
        try {
            config_.truncation.mode = parseTruncationMode(truncation_mode_);
        } catch (const ConfigError& e) {
            failConfig(std::string("option '") + e.what());
        }
        try {
            config_.merge_divisions = parseMergePoints(merge_points_);
        } catch (const ConfigError&) {
            failConfig("option 'merge_points' must be auto, none, voxel or half_voxel, got '" +
                       merge_points_ + "'");
        }
        validateAtsdfConfig(config_, voxel_size_m_, std::string(name()));
        resolved_ = resolveAtsdfConfig(config_, voxel_size_m_);
        validateDynamicRemovalConfig(dynamic_, std::string(name()));
    }
    void declareLayers(LayerSpec& spec) const override {
        spec.reads(layers::kScans);
        spec.writes(layers::kTsdf);
    }
    void run(Context& ctx) override {
        const Dataset& dataset = ctx.dataset();
        std::shared_ptr<VoxelMap> map = makeVoxelMap(config_, voxel_size_m_);
        AtsdfIntegrator integrator(*map, config_);
        // Streamed tiled runs finish tiles from this map while the scans come in; a scan
        // changes it at most maxUpdateReach past a point, plus the block statistics a point
        // reads (its block and their 26 neighbours: within 3.5 leaves of the point).
        ContextBuilder::setMap(ctx, map);
        const double leaf_m = 8.0 * voxel_size_m_;
        const std::vector<std::size_t> frames =
            ctx.beginScanStream(maxUpdateReach(resolved_, voxel_size_m_) + 4.0 * leaf_m);
        // Moving objects out of the map (issue 33): each scan's dynamic points are dropped
        // before it is integrated, in the read-ahead task (docs/dynamic.md).
        DynamicRemovalStep dynamic(ctx, dynamic_);
        const ScanStream* stream = ContextBuilder::scanStream(ctx);
        const PointRegion* region =
            stream && !config_.space_carving ? stream->pointRegion() : nullptr;
        // A distributed run: each scan's moving points are decided by one process for all
        // (issue 37), instead of by every process that integrates the scan.
        if (stream && stream->processes() > 1) {
            dynamic.shareDecisions(stream->sharedFrames(), frames,
                                   [stream](const std::string& mine) { return stream->allGather(mine); });
        }
        std::size_t outside_region = 0;
        DatasetIntegration run;
        {
            // Scan i + 1 is read while scan i is integrated (integrateDataset).
            Progress progress("integrate.atsdf", frames.size(), ctx.quiet());
            run = integrateDataset(
                dataset, integrator, frames,
                [&](std::size_t frame) {
                    progress.tick();
                    ctx.scanIntegrated(frame);
                },
                dynamic.filter(), pointRegionFilter(dataset, region, outside_region));
        }
        dynamic.finish(ctx, std::string(name()));
        const ScanReadStats& read_total = run.read;
        const double seconds = run.seconds - run.on_scan_s;
        integrator.finalize();

        const IntegrationStats& t = integrator.totals();
        const std::string s(name());
        Report& r = ctx.report();
        r.stage(s, "scans", t.scans);
        r.stage(s, "reference_points", resolved_.truncation.reference_points);
        r.stage(s, "truncation_min_m_used", resolved_.truncation.min_m);
        r.stage(s, "truncation_max_m_used", resolved_.truncation.max_m);
        r.stage(s, "updates_per_point",
                t.points_integrated ? static_cast<double>(t.voxel_updates) / static_cast<double>(t.points_integrated) : 0.0);
        r.stage(s, "points_read", read_total.points_read);
        r.stage(s, "points_integrated", t.points_integrated);
        // Distributed runs: points no tile of this process needs (PointRegion), not integrated.
        r.stage(s, "dropped_outside_process_tiles", outside_region);
        r.stage(s, "dropped_non_finite", read_total.dropped_non_finite + t.dropped_non_finite);
        r.stage(s, "dropped_range", read_total.dropped_range + t.dropped_range);
        r.stage(s, "dropped_at_origin", t.dropped_at_origin);
        r.stage(s, "voxel_updates", t.voxel_updates);
        r.stage(s, "rays", t.rays);
        r.stage(s, "rays_per_point",
                t.points_integrated ? static_cast<double>(t.rays) / static_cast<double>(t.points_integrated) : 0.0);
        r.stage(s, "carving_updates", t.carving_updates);
        r.stage(s, "leaves_reloaded", t.leaves_reloaded);
        r.stage(s, "leaves_retired", t.leaves_retired);
        const std::size_t active = static_cast<std::size_t>(map->activeVoxelCount());
        const std::size_t leaves = static_cast<std::size_t>(map->leafCount());
        r.stage(s, "voxels_active", active);
        r.stage(s, "leaves", leaves);
        r.stage(s, "blocks_with_stats", map->blockStats().size());
        r.stage(s, "bytes_per_leaf_stats", map->blockStats().bytesPerBlock());
        const double grid_bytes = static_cast<double>(map->tsdfMemoryBytes());
        r.stage(s, "bytes_per_active_voxel", active ? grid_bytes / static_cast<double>(active) : 0.0);
        r.stage(s, "read_wait_s", run.read_wait_s);
        r.stage(s, "phase_bin_s", t.bin_s);
        r.stage(s, "phase_stats_s", t.stats_s);
        r.stage(s, "phase_alloc_s", t.alloc_s);
        r.stage(s, "phase_update_s", t.update_s);
        r.stage(s, "phase_retire_s", t.retire_s);
        r.stage(s, "seconds", seconds);
        r.stage(s, "ms_per_scan", t.scans ? 1e3 * seconds / static_cast<double>(t.scans) : 0.0);
        r.stage(s, "mpts_per_s", seconds > 0 ? 1e-6 * static_cast<double>(t.points_integrated) / seconds : 0.0);
        std::ostringstream os;
        os << "integrate.atsdf: " << t.scans << " scans, " << t.points_integrated << " points, "
           << active << " active voxels in " << leaves << " leaves";
        logInfo(os.str());
    }

    AtsdfStageSettings settings() const { return {voxel_size_m_, config_}; }

private:
    double voxel_size_m_ = kDefaultVoxelSizeM;
    std::string truncation_mode_;
    std::string merge_points_;
    AtsdfConfig config_;    ///< as given (voxel counts, kMergeAuto)
    AtsdfConfig resolved_;  ///< at voxel_size_m_, for the report
    DynamicRemovalConfig dynamic_;
};

/// mesh.marching_cubes: zero level set of the tsdf as a welded triangle mesh.
class MarchingCubesStage : public Stage {
public:
    std::string_view name() const override { return "mesh.marching_cubes"; }
    std::string_view summary() const override {
        return "Marching cubes over the observed tsdf (welded vertices, vertex normals)";
    }
    void declareOptions(OptionSpec& spec) override {
        const MarchingCubesConfig d;  // the defaults: MarchingCubesConfig's
        spec.add("min_weight", "Mesh a cube only if its 8 corners have at least this weight",
                 config_.min_weight, d.min_weight);
        spec.add("min_component_faces", "Remove connected components with fewer faces (0 = keep all)",
                 config_.min_component_faces, d.min_component_faces);
    }
    void initialize() override {
        if (!(config_.min_weight >= 0.0) || !std::isfinite(config_.min_weight)) {
            std::ostringstream os;
            os << "option 'min_weight' must be finite and >= 0, got " << config_.min_weight;
            failConfig(os.str());
        }
        if (config_.min_component_faces < 0) {
            failConfig("option 'min_component_faces' must be >= 0, got " +
                       std::to_string(config_.min_component_faces));
        }
    }
    void declareLayers(LayerSpec& spec) const override {
        spec.reads(layers::kTsdf);
        spec.writes(layers::kMesh);
    }
    void run(Context& ctx) override {
        Timer timer;
        MeshStats stats;
        // Tiled runs: the tile's core cubes plus its halo (halo faces marked, TileFaces.h).
        ctx.setMesh(ctx.hasTile() ? extractMeshRegion(ctx.map(), config_, ctx.tile().region, &stats)
                                  : extractMesh(ctx.map(), config_, &stats));
        const std::string s(name());
        Report& r = ctx.report();
        r.stage(s, "faces", stats.faces);
        r.stage(s, "vertices", stats.vertices);
        r.stage(s, "cubes_meshed", stats.cubes_meshed);
        r.stage(s, "components_removed", stats.components_removed);
        r.stage(s, "faces_removed_small_components", stats.faces_removed_small_components);
        r.stage(s, "faces_rejected_nonmanifold", stats.faces_rejected_nonmanifold);
        if (ctx.hasTile()) {
            r.stage(s, "halo_faces", stats.halo_faces);
            // Occluders beyond the halo: visibility tests see what hides the tile from a view.
            const MeshRegion& occ = ctx.tile().occluder_region;
            if (occ.halo_vox > ctx.tile().region.halo_vox) {
                MeshStats occ_stats;
                ctx.setOccluderMesh(extractMeshRegion(ctx.map(), config_, occ, &occ_stats));
                r.stage(s, "occluder_faces", occ_stats.faces);
            }
        }
        r.stage(s, "seconds", timer.elapsedSeconds());
    }

private:
    MarchingCubesConfig config_;
};

}  // namespace

AtsdfStageSettings atsdfStageSettings(const Stage& stage) {
    const auto* atsdf = dynamic_cast<const IntegrateAtsdfStage*>(&stage);
    if (atsdf == nullptr)
        throw InvalidInput("atsdfStageSettings: stage '" + std::string(stage.name()) +
                           "' is not integrate.atsdf");
    return atsdf->settings();
}

void registerTsdfStages(StageRegistry& registry) {
    registry.add<IntegrateAtsdfStage>();
    registry.add<MarchingCubesStage>();
}

}  // namespace vdbmap::detail
