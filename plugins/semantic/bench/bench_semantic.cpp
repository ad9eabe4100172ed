// SPDX-License-Identifier: Apache-2.0
// Speed of the semantic labelling on a synthetic street corridor (ground + two facades) seen
// by cameras driving along it: visibility (with Embree occlusion), votes and the MRF, in faces
// per second, plus peak memory; with --scans, the LiDAR votes of that many labelled scans
// (HDL-64E-like, ray cast against the corridor, 10 % of the labels flipped), combined with
// the image votes, and the geometric smoothness weights. Results and commands:
// docs/results/semantic.md.
//   bench_semantic --faces 1000000 --views 200 --scans 200 --threads 2
#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include <random>

#include "GeometricSmoothness.h"
#include "LidarVotes.h"
#include "SemanticFusion.h"
#include "SemanticVotes.h"
#include "VoteCombination.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/Visibility.h"

using namespace vdbmap;

namespace {

// A grid of quads spanning origin + [0, nu] * du + [0, nv] * dv, normals du x dv.
void addSheet(TriMesh& mesh, const Vec3f& origin, const Vec3f& du, const Vec3f& dv, int nu,
              int nv) {
    std::vector<TriMesh::VertexHandle> v;
    for (int j = 0; j <= nv; ++j) {
        for (int i = 0; i <= nu; ++i) {
            const Vec3f p = origin + du * float(i) + dv * float(j);
            v.push_back(mesh.add_vertex(TriMesh::Point(p.x(), p.y(), p.z())));
        }
    }
    auto at = [&](int i, int j) { return v[static_cast<std::size_t>(j * (nu + 1) + i)]; };
    for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
            mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Semantic labelling speed on a synthetic street"};
    double faces_target = 1e6;
    int num_views = 200;
    int threads = 2;
    double length_m = 200.0;
    bool occlusion = true;
    int num_scans = 0;
    double azimuth_step_deg = 0.18;
    app.add_option("--faces", faces_target, "Approximate number of faces");
    app.add_option("--views", num_views, "Number of camera views along the street");
    app.add_option("--threads", threads, "Worker threads");
    app.add_option("--length", length_m, "Street length in metres");
    app.add_option("--occlusion", occlusion, "Occlusion test on/off");
    app.add_option("--scans", num_scans, "Labelled LiDAR scans along the street (0 = none)");
    app.add_option("--azimuth-step", azimuth_step_deg,
                   "LiDAR azimuth step, deg (0.18: 2000 x 64 rays per scan)");
    CLI11_PARSE(app, argc, argv);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(std::max(1, threads)));
    setLogLevel(LogLevel::Warn);

    // Ground 10 m wide, facades 6 m high: faces = 2 L (W + 2 H) / s^2.
    const double width_m = 10.0, height_m = 6.0;
    const double cell_m = std::sqrt(2.0 * length_m * (width_m + 2.0 * height_m) / faces_target);
    const int nl = static_cast<int>(length_m / cell_m);
    const int nw = static_cast<int>(width_m / cell_m);
    const int nh = static_cast<int>(height_m / cell_m);
    const float s = static_cast<float>(cell_m);
    const float half_w = static_cast<float>(width_m / 2);
    TriMesh mesh;
    addSheet(mesh, {0, -half_w, 0}, {s, 0, 0}, {0, s, 0}, nl, nw);            // ground, +z
    addSheet(mesh, {0, -half_w, 0}, {0, 0, s}, {s, 0, 0}, nh, nl);            // left wall, +y
    addSheet(mesh, {0, half_w, 0}, {s, 0, 0}, {0, 0, s}, nl, nh);             // right wall, -y

    std::vector<View> views;
    for (int k = 0; k < num_views; ++k) {
        View view;
        view.frame = static_cast<std::size_t>(k);
        view.intrinsics.width = 1242;
        view.intrinsics.height = 375;
        view.intrinsics.fx = view.intrinsics.fy = 720.0;
        view.intrinsics.cx = 620.5;
        view.intrinsics.cy = 187.5;
        Isometry3d T_W_C = Isometry3d::Identity();
        // Camera z along world +x, x along world -y, y along world -z (KITTI-like).
        T_W_C.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
        T_W_C.translation() = Vec3d(length_m * k / num_views, 0.0, 1.65);
        view.T_C_W = T_W_C.inverse();
        views.push_back(view);
    }
    // Class stripes, a little noise-like variety so that faces get several votes.
    cv::Mat image(375, 1242, CV_8UC1);
    for (int v = 0; v < image.rows; ++v) {
        for (int u = 0; u < image.cols; ++u) {
            image.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>((u / 40 + v / 25) % 21);
        }
    }
    const LabelSet labels = LabelSet::defaults();

    Timer total;
    Timer step;
    const Raycaster raycaster = Raycaster::fromMesh(mesh);
    const double t_bvh = step.elapsedSeconds();
    step.reset();
    VisibilityOptions vis_options;
    vis_options.max_depth_m = 60.0;
    const Visibility vis =
        computeVisibility(mesh, views, vis_options, occlusion ? &raycaster : nullptr);
    const double t_vis = step.elapsedSeconds();
    step.reset();
    const semantic::FaceVotes votes = semantic::accumulateVotes(
        vis, views.size(), [&](std::size_t) { return image; }, labels);
    const double t_votes = step.elapsedSeconds();
    step.reset();
    // LiDAR: scans simulated before the clock runs again (not part of the labelling).
    Timer sim_clock;
    std::vector<std::vector<Vec3f>> scan_points(static_cast<std::size_t>(num_scans));
    std::vector<std::vector<std::uint32_t>> scan_classes(static_cast<std::size_t>(num_scans));
    std::size_t lidar_points = 0;
    {
        std::vector<Vec3f> dirs;
        for (double az = 0; az < 360.0; az += azimuth_step_deg) {
            for (int b = 0; b < 64; ++b) {
                const double el = (2.0 - 26.8 * b / 63.0) * M_PI / 180.0;
                const double a = az * M_PI / 180.0;
                dirs.emplace_back(float(std::cos(el) * std::cos(a)), float(std::cos(el) * std::sin(a)),
                                  float(std::sin(el)));
            }
        }
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u01(0.0, 1.0);
        std::vector<std::optional<Raycaster::Hit>> hits;
        for (int k = 0; k < num_scans; ++k) {
            const Vec3f origin(float(length_m * (k + 0.5) / num_scans), 0.0f, 1.73f);
            raycaster.intersect({origin}, dirs, 120.0f, hits);
            for (std::size_t i = 0; i < hits.size(); ++i) {
                if (!hits[i]) continue;
                const Vec3f n = hits[i]->normal_unit;
                std::uint32_t cls = std::abs(n.z()) > 0.5f ? 0u : 2u;  // road : building
                if (u01(rng) < 0.1) cls = static_cast<std::uint32_t>(rng() % labels.size());
                scan_points[k].push_back(origin + dirs[i] * hits[i]->distance);
                scan_classes[k].push_back(cls);
            }
            lidar_points += scan_points[k].size();
        }
    }
    const double t_sim = sim_clock.elapsedSeconds();
    step.reset();
    std::vector<Vec3f> vertices;
    for (const auto vh : mesh.vertices()) {
        const auto& p = mesh.point(vh);
        vertices.emplace_back(p[0], p[1], p[2]);
    }
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (const auto fh : mesh.faces()) {
        std::array<std::uint32_t, 3> t{};
        int c = 0;
        for (const auto vh : mesh.fv_range(fh)) t[c++] = static_cast<std::uint32_t>(vh.idx());
        triangles.push_back(t);
    }
    semantic::FaceVotes lidar_votes;
    if (num_scans > 0) {
        semantic::LidarVoteAccumulator acc(vertices, triangles, labels.size(), 0.1f);
        for (int k = 0; k < num_scans; ++k) {
            acc.add(scan_points[k], scan_classes[k]);
            std::vector<Vec3f>().swap(scan_points[k]);
            std::vector<std::uint32_t>().swap(scan_classes[k]);
        }
        lidar_votes = acc.finish();
    }
    const semantic::FaceVotes combined = semantic::combineVotes(votes, lidar_votes, 1.0);
    const double t_lidar = step.elapsedSeconds();
    step.reset();
    const auto adjacency = faceAdjacency(mesh);
    std::vector<float> weights = semantic::geometricEdgeWeights(
        vertices, triangles, adjacency, Vec3f::UnitZ(), semantic::GeometricSmoothnessOptions{});
    semantic::uniformBetweenObserved(weights, adjacency, combined);
    semantic::FusionOptions fusion;
    fusion.edge_weights = &weights;
    const semantic::FusionResult result = semantic::fuseLabels(combined, adjacency, labels, fusion);
    const double t_mrf = step.elapsedSeconds();
    const double t_total = total.elapsedSeconds() - t_sim;  // without simulating the scans
    const double f = static_cast<double>(mesh.n_faces());
    std::printf("faces %zu views %d threads %d observations %zu observed %zu\n", mesh.n_faces(),
                num_views, threads, vis.obs.size(), result.observed_faces);
    std::printf("scans %d lidar_points %zu\n", num_scans, lidar_points);
    std::printf("bvh_s %.2f visibility_s %.2f votes_s %.2f lidar_votes_s %.2f mrf_s %.2f "
                "total_s %.2f\n",
                t_bvh, t_vis, t_votes, t_lidar, t_mrf, t_total);
    std::printf("faces_per_s visibility %.0f votes %.0f mrf %.0f total %.0f\n", f / t_vis,
                f / t_votes, f / t_mrf, f / t_total);
    std::printf("energy %.1f -> %.1f sweeps %d peak_memory_mb %.0f\n", result.initial_energy,
                result.final_energy, result.sweeps,
                static_cast<double>(peakMemoryBytes()) / (1024.0 * 1024.0));
    return 0;
}
