// SPDX-License-Identifier: Apache-2.0
// Integration / meshing benchmark of the adaptive TSDF (issue #3). A KITTI-like synthetic
// street (ground, facades, parked cars, poles, tree crowns) is ray-cast in closed form by a
// 64-beam spinning LiDAR (~120k points per scan) moving 1 m per scan. Scans are generated (or
// loaded from --cache) before timing. Prints one JSON object per run on stdout.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "ProjectiveBaseline.h"
#include "VdbFusionBaseline.h"
#include "support/PlainAtsdfConfig.h"
#include "support/SimLidar.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/pipeline/DatasetSection.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/BlockStats.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"

using namespace vdbmap;
using namespace vdbmap::test;

namespace {

double processCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

SimScene streetScene() {
    SimScene s;
    s.add(SimPlane{Vec3d(0, 0, 0), Vec3d::UnitZ()});
    s.add(SimPlane{Vec3d(0, 9, 0), -Vec3d::UnitY()});
    s.add(SimPlane{Vec3d(0, -9, 0), Vec3d::UnitY()});
    for (int i = -10; i < 40; ++i) {
        const double x = 6.0 * i;
        if (i % 3 != 0) s.add(SimBox{Vec3d(x, 5.2, 0.0), Vec3d(x + 4.2, 7.0, 1.5)});
        if (i % 4 != 1) s.add(SimBox{Vec3d(x + 1.0, -7.0, 0.0), Vec3d(x + 5.4, -5.2, 1.6)});
        if (i % 2 == 0) {
            s.add(SimBox{Vec3d(x + 2.9, 7.6, 0.0), Vec3d(x + 3.1, 7.8, 5.0)});
            s.add(SimSphere{Vec3d(x + 3.0, -7.7, 4.5), 1.4});
            s.add(SimBox{Vec3d(x + 2.9, -7.8, 0.0), Vec3d(x + 3.1, -7.6, 3.5)});
        }
    }
    return s;
}

std::vector<std::vector<Vec3f>> makeScans(int num_scans, const std::string& cache) {
    std::vector<std::vector<Vec3f>> scans(static_cast<std::size_t>(num_scans));
    if (!cache.empty()) {
        std::ifstream in(cache, std::ios::binary);
        std::int32_t n = 0;
        if (in.read(reinterpret_cast<char*>(&n), sizeof(n)) && n >= num_scans) {
            for (auto& s : scans) {
                std::uint64_t m = 0;
                in.read(reinterpret_cast<char*>(&m), sizeof(m));
                s.resize(m);
                in.read(reinterpret_cast<char*>(s.data()), static_cast<std::streamsize>(m * sizeof(Vec3f)));
            }
            if (in) return scans;
        }
    }
    const SimScene scene = streetScene();
    SimLidarConfig lidar;
    lidar.beams = 64;
    lidar.azimuth_steps = 1875;
    lidar.noise_sigma_m = 0.02;
    tbb::parallel_for(0, num_scans, [&](int i) {
        scans[static_cast<std::size_t>(i)] =
            simulateScan(scene, lidar, poseAt(Vec3d(1.0 * i, 0.3 * std::sin(0.1 * i), 1.73)),
                         static_cast<std::uint64_t>(i));
    });
    if (!cache.empty()) {
        std::ofstream out(cache, std::ios::binary);
        const std::int32_t n = num_scans;
        out.write(reinterpret_cast<const char*>(&n), sizeof(n));
        for (const auto& s : scans) {
            const std::uint64_t m = s.size();
            out.write(reinterpret_cast<const char*>(&m), sizeof(m));
            out.write(reinterpret_cast<const char*>(s.data()), static_cast<std::streamsize>(m * sizeof(Vec3f)));
        }
    }
    return scans;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

/// --pipeline mode: runs the pipeline file (its integrate stage, with --set overrides) as
/// `vdbmap run` does, `repeat` times, each followed by the VDBFusion port (VdbFusionBaseline.h,
/// the `baseline_*` figures) and the leaner projective variant (`lean_baseline_*`) at the same
/// voxel size and eps_max on the same scans in this process (1 thread, scans read and converted
/// beforehand: their reading is left out). Prints medians and their ratios.
int runPipelineMode(const std::string& config, std::vector<std::string> sets, int repeat,
                    int threads, const std::string& out_dir, const std::string& baseline_mesh) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    sets.push_back("output.write_map=false");
    sets.push_back("output.write_mesh=false");
    // The baseline's scans, read once (as the same dataset section of the pipeline).
    std::vector<std::string> dataset_sets;
    for (const std::string& set : sets)
        if (set.rfind("dataset.", 0) == 0) dataset_sets.push_back(set);
    const DatasetSection section = loadDatasetSection(config, dataset_sets);
    const auto dataset = Dataset::open(section.config, section.base_dir);
    std::vector<std::vector<Vec3f>> scans_W;
    std::vector<std::vector<Eigen::Vector3d>> scans_W_double;  // as VDBFusion's API takes a scan
    std::vector<Vec3d> origins;
    for (std::size_t i = 0; i < dataset->numFrames(); ++i) {
        const PointCloud cloud = dataset->loadScan(i);
        const Eigen::Isometry3f T = dataset->frame(i).T_W_L.cast<float>();
        std::vector<Vec3f> pw;
        pw.reserve(cloud.points.size());
        for (const Vec3f& p : cloud.points) pw.push_back(T * p);
        std::vector<Eigen::Vector3d> pw_double;
        pw_double.reserve(pw.size());
        for (const Vec3f& p : pw) pw_double.push_back(p.cast<double>());
        scans_W.push_back(std::move(pw));
        scans_W_double.push_back(std::move(pw_double));
        origins.push_back(dataset->frame(i).T_W_L.translation());
    }
    std::vector<double> ours_s, base_s, lean_s, ratio, lean_ratio;
    nlohmann::json stage;
    std::size_t base_updates = 0, lean_updates = 0;
    const std::function<float(float)> constant_weight = [](float /*sdf*/) { return 1.0f; };
    for (int r = 0; r < repeat; ++r) {
        auto pipeline = Pipeline::fromFile(config, sets);
        Report report;
        pipeline->run(out_dir, report, true);
        std::ifstream in(std::filesystem::path(out_dir) / "report.json");
        const nlohmann::json j = nlohmann::json::parse(in);
        stage = j.at("stages").at("integrate.atsdf");
        ours_s.push_back(stage.at("seconds").get<double>());
        const double voxel = j.at("config").at("stages").at(0).at("options").at("voxel_size_m").get<double>();
        const double eps_max = stage.at("truncation_max_m_used").get<double>();
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        {
            bench::VdbFusionBaseline peer(voxel, static_cast<float>(eps_max));
            base_updates = 0;
            Timer tb;
            for (std::size_t i = 0; i < scans_W_double.size(); ++i)
                base_updates += peer.integrate(scans_W_double[i], origins[i], constant_weight);
            base_s.push_back(tb.elapsedSeconds());
        }
        bench::ProjectiveBaseline base(voxel, static_cast<float>(eps_max));
        lean_updates = 0;
        Timer tl;
        for (std::size_t i = 0; i < scans_W.size(); ++i) lean_updates += base.integrate(scans_W[i], origins[i]);
        lean_s.push_back(tl.elapsedSeconds());
        if (!baseline_mesh.empty() && r + 1 == repeat) {
            // The baseline's map meshed by our marching cubes (default settings), for `vdbmap eval`.
            const float weight_cap = 100.0f;
            VoxelMap map(voxel, static_cast<float>(eps_max), weight_cap);
            base.forEachVoxel([&](const openvdb::Coord& ijk, float sdf, float w) {
                map.setVoxel(ijk, sdf, std::min(w, weight_cap));
            });
            // The baseline's voxel v is the cell [v, v + 1) (centre v + 0.5, OpenVDB's DDA), ours
            // is centred on v: shift the mesh by half a voxel.
            auto mesh = extractMesh(map, MarchingCubesConfig{});
            const float half = static_cast<float>(0.5 * voxel);
            for (auto v : mesh->vertices()) mesh->point(v) += TriMesh::Point(half, half, half);
            writeMeshPly(baseline_mesh, *mesh);
        }
        ratio.push_back(base_s.back() / ours_s.back());
        lean_ratio.push_back(lean_s.back() / ours_s.back());
    }
    const double points = stage.at("points_integrated").get<double>();
    nlohmann::json j;
    j["mode"] = "pipeline";
    j["config"] = config;
    j["sets"] = sets;
    j["threads"] = threads;
    j["repeat"] = repeat;
    j["points"] = points;
    j["integrate_s"] = ours_s;
    j["baseline_s"] = base_s;
    j["integrate_s_median"] = median(ours_s);
    j["baseline_s_median"] = median(base_s);
    j["mpts_per_s_median"] = 1e-6 * points / median(ours_s);
    j["baseline_mpts_per_s_median"] = 1e-6 * points / median(base_s);
    j["speedup_of_medians"] = median(base_s) / median(ours_s);
    j["speedup_median_of_pairs"] = median(ratio);
    j["updates_per_point"] = stage.at("updates_per_point");
    j["baseline_updates_per_point"] = static_cast<double>(base_updates) / points;
    // The leaner projective variant (ProjectiveBaseline.h), for comparison with earlier tables.
    j["lean_baseline_s"] = lean_s;
    j["lean_baseline_s_median"] = median(lean_s);
    j["lean_speedup_of_medians"] = median(lean_s) / median(ours_s);
    j["lean_speedup_median_of_pairs"] = median(lean_ratio);
    j["lean_baseline_updates_per_point"] = static_cast<double>(lean_updates) / points;
    j["read_wait_s"] = stage.at("read_wait_s");
    for (const char* k : {"phase_bin_s", "phase_stats_s", "phase_alloc_s", "phase_update_s", "phase_retire_s"})
        if (stage.contains(k)) j[k] = stage.at(k);
    std::cout << j.dump() << std::endl;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vdbmap adaptive TSDF integration benchmark"};
    int num_scans = 100, threads = 1;
    double voxel = 0.10, eps_min = 0.10, eps_max = 0.30;
    std::string mode = "adaptive", cache;
    bool carving = false, baseline = false;
    app.add_option("--scans", num_scans, "number of scans (>= 1)");
    app.add_option("--threads", threads, "TBB threads");
    app.add_option("--voxel", voxel, "voxel size in m");
    app.add_option("--eps-min", eps_min, "truncation min in m");
    app.add_option("--eps-max", eps_max, "truncation max in m (the fixed value in fixed mode)");
    app.add_option("--mode", mode, "adaptive | fixed");
    app.add_option("--cache", cache, "binary file caching the generated scans");
    app.add_flag("--space-carving", carving, "enable space carving");
    // The plain integrator this benchmark's recorded figures were measured with (eps in
    // metres, no merging, no band to the next ring), not the stage's defaults.
    const AtsdfConfig plain = vdbmap::test::plainAtsdfConfig();
    int working_set = plain.working_set_scans;
    app.add_option("--working-set", working_set, "scans a leaf stays dense (working_set_scans)");
    app.add_flag("--baseline", baseline,
                 "also run the projective VDBFusion-style baseline (1 thread, fixed eps_max) on the "
                 "same scans, after our integrator, and report both");
    std::string pipeline_config, pipeline_out = "out/bench_pipeline";
    std::vector<std::string> pipeline_sets;
    int repeat = 5;
    app.add_option("--pipeline", pipeline_config,
                   "time what `vdbmap run` does: this pipeline's integrate stage (scan reading "
                   "included) against the baseline on the same scans (e.g. bench/run_integration.yaml)");
    app.add_option("--set", pipeline_sets, "--pipeline: override, as `vdbmap run --set`");
    app.add_option("--repeat", repeat, "--pipeline: runs (medians are reported)");
    app.add_option("--out", pipeline_out, "--pipeline: output folder (report.json)");
    std::string baseline_mesh;
    app.add_option("--baseline-mesh", baseline_mesh,
                   "--pipeline: write the baseline's map, meshed by marching cubes, to this PLY");
    CLI11_PARSE(app, argc, argv);
    try {
        if (!pipeline_config.empty()) {
            if (repeat < 1 || threads < 1) throw std::runtime_error("--repeat and --threads must be >= 1");
            return runPipelineMode(pipeline_config, pipeline_sets, repeat, threads, pipeline_out,
                                   baseline_mesh);
        }
        if (num_scans < 1 || threads < 1) throw std::runtime_error("--scans and --threads must be >= 1");
        const auto scans = makeScans(num_scans, cache);
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
        VoxelMap map(voxel, static_cast<float>(eps_max), static_cast<float>(plain.max_weight));
        AtsdfConfig cfg = plain;
        cfg.truncation.mode = parseTruncationMode(mode);
        cfg.truncation.min_m = eps_min;
        cfg.truncation.max_m = eps_max;
        // As the stage does: n_ref from the default surface density, scaled with the block size.
        cfg.truncation.reference_points = referencePointsForDensity(156.25, voxel);
        cfg.space_carving = carving;
        cfg.working_set_scans = working_set;
        AtsdfIntegrator integrator(map, cfg);
        std::vector<double> ms;
        std::size_t points = 0;
        const double cpu0 = processCpuSeconds();
        // The TSDF's memory after every scan (working tree + compact store), its time left out.
        double probe_s = 0.0, probe_cpu_s = 0.0;
        double peak_bytes = 0.0, peak_working_bytes = 0.0, last_bytes_per_voxel = 0.0;
        Timer total;
        for (int i = 0; i < num_scans; ++i) {
            const auto& pts = scans[static_cast<std::size_t>(i)];
            Timer t;
            const IntegrationStats s = integrator.integrateScan(
                pts, poseAt(Vec3d(1.0 * i, 0.3 * std::sin(0.1 * i), 1.73)));
            ms.push_back(1e3 * t.elapsedSeconds());
            points += s.points_integrated;
            Timer tp;
            const double c0 = processCpuSeconds();
            const double bytes = static_cast<double>(map.tsdfMemoryBytes());
            peak_bytes = std::max(peak_bytes, bytes);
            peak_working_bytes = std::max(peak_working_bytes, static_cast<double>(map.workingTsdf()->memUsage()));
            last_bytes_per_voxel = bytes / static_cast<double>(map.activeVoxelCount());
            probe_cpu_s += processCpuSeconds() - c0;
            probe_s += tp.elapsedSeconds();
        }
        const double seconds = total.elapsedSeconds() - probe_s;
        const double cpu_seconds = processCpuSeconds() - cpu0 - probe_cpu_s;
        const double leaves_before_finalize = static_cast<double>(map.leafCount());
        Timer tf;
        integrator.finalize();
        const double finalize_s = tf.elapsedSeconds();
        Timer tm;
        MeshStats mesh_stats;
        const auto mesh = extractMesh(map, MarchingCubesConfig{}, &mesh_stats);
        const double mesh_s = tm.elapsedSeconds();
        std::sort(ms.begin(), ms.end());
        const double active = static_cast<double>(map.activeVoxelCount());
        const double leaves = static_cast<double>(map.leafCount());
        const double grid_bytes = static_cast<double>(map.tsdfMemoryBytes());
        // Active voxels per leaf: how full the allocated 8^3 leaves are.
        std::vector<int> fill;
        for (const TsdfLeafView& leaf : map.leafViews()) {
            int n = 0;
            leaf.forEachObserved([&](openvdb::Index) { ++n; });
            fill.push_back(n);
        }
        std::sort(fill.begin(), fill.end());
        auto fillAt = [&](double q) {
            return fill.empty() ? 0 : fill[static_cast<std::size_t>(q * (fill.size() - 1))];
        };
        nlohmann::json j;
        j["mode"] = mode;
        j["threads"] = threads;
        j["voxel_m"] = voxel;
        j["eps_min_m"] = eps_min;
        j["eps_max_m"] = eps_max;
        j["scans"] = num_scans;
        j["points"] = points;
        j["points_per_scan"] = static_cast<double>(points) / num_scans;
        j["voxel_updates"] = integrator.totals().voxel_updates;
        j["phase_bin_s"] = integrator.totals().bin_s;
        j["phase_stats_s"] = integrator.totals().stats_s;
        j["phase_alloc_s"] = integrator.totals().alloc_s;
        j["phase_update_s"] = integrator.totals().update_s;
        j["phase_retire_s"] = integrator.totals().retire_s;
        j["working_set_scans"] = working_set;
        j["leaves_reloaded"] = integrator.totals().leaves_reloaded;
        j["leaves_retired"] = integrator.totals().leaves_retired;
        j["seconds"] = seconds;
        j["mpts_per_s"] = 1e-6 * static_cast<double>(points) / seconds;
        // CPU time of all threads: on a shared machine less noisy than the wall time.
        j["cpu_s"] = cpu_seconds;
        j["mpts_per_cpu_s"] = 1e-6 * static_cast<double>(points) / cpu_seconds;
        j["ns_per_voxel_update"] = 1e9 * seconds / static_cast<double>(integrator.totals().voxel_updates);
        j["ms_per_scan_median"] = ms[ms.size() / 2];
        j["finalize_s"] = finalize_s;
        j["mesh_s"] = mesh_s;
        j["faces"] = mesh_stats.faces;
        j["vertices"] = mesh_stats.vertices;
        j["active_voxels"] = active;
        j["leaves"] = leaves;
        j["leaves_before_finalize"] = leaves_before_finalize;
        j["leaf_fill_p10_p50_p90"] = {fillAt(0.1), fillAt(0.5), fillAt(0.9)};
        j["bytes_per_active_voxel"] = grid_bytes / active;
        j["bytes_per_leaf_grids"] = grid_bytes / leaves;
        j["mean_leaf_fill"] = active / leaves;
        // During integration (after each scan): both stores, and the working tree alone.
        j["peak_tsdf_mb"] = peak_bytes / (1024.0 * 1024.0);
        j["peak_working_mb"] = peak_working_bytes / (1024.0 * 1024.0);
        // After the last scan, before finalize: the working set of the last scans still dense.
        j["bytes_per_active_voxel_before_finalize"] = last_bytes_per_voxel;
        // A dense 8^3 leaf of packed values (what every leaf would cost without the compact store).
        j["bytes_per_dense_leaf"] = static_cast<double>(TsdfLeaf(openvdb::Coord(0), 0u).memUsage());
        j["bytes_per_leaf_stats"] = map.blockStats().bytesPerBlock();
        j["blocks_with_stats"] = map.blockStats().size();
        j["peak_rss_mb"] = static_cast<double>(peakMemoryBytes()) / (1024.0 * 1024.0);
        if (baseline) {
            // Same scans and poses, same process; the baseline is single-threaded by design.
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            bench::ProjectiveBaseline base(voxel, static_cast<float>(eps_max));
            std::size_t base_updates = 0;
            Timer tb;
            for (int i = 0; i < num_scans; ++i) {
                const Isometry3d T_W_L = poseAt(Vec3d(1.0 * i, 0.3 * std::sin(0.1 * i), 1.73));
                std::vector<Vec3f> points_W;
                points_W.reserve(scans[static_cast<std::size_t>(i)].size());
                const Eigen::Isometry3f T = T_W_L.cast<float>();
                for (const Vec3f& p : scans[static_cast<std::size_t>(i)]) points_W.push_back(T * p);
                base_updates += base.integrate(points_W, T_W_L.translation());
            }
            const double base_s = tb.elapsedSeconds();
            j["baseline_seconds"] = base_s;
            j["baseline_mpts_per_s"] = 1e-6 * static_cast<double>(points) / base_s;
            j["baseline_ns_per_voxel_update"] = 1e9 * base_s / static_cast<double>(base_updates);
            j["baseline_bytes_per_active_voxel"] =
                static_cast<double>(base.memoryBytes()) / static_cast<double>(base.activeVoxelCount());
            j["speedup_vs_baseline"] = base_s / seconds;
        }
        std::cout << j.dump() << std::endl;
    } catch (const std::exception& e) {
        std::cerr << "bench_integration: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
