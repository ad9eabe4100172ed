// SPDX-License-Identifier: Apache-2.0
// Texturing speed and memory on a synthetic street canyon (two facades and the road) seen by a
// forward camera of KITTI geometry (1242 x 375, fx 720) driving along it. Images are rendered
// analytically, PNG-encoded once in memory and decoded on every load, as from disk. Times
// every step of texture.mrf (visibility, data term, photo-consistency, MRF, atlas, global
// adjustment) and the peak memory after each. Results: docs/benchmarks/texture.md.
//
//   bench_texture --faces 1000000 --views 200 --threads 2
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "TexturePipeline.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/Visibility.h"

namespace {

using vdbmap::Vec3f;
constexpr double kHalfWidth = 6.0;  // facades at x = +-6 m
constexpr double kGroundY = 1.7;    // camera 1.7 m above the road (y down)
constexpr double kTopY = -6.0;      // facade top
constexpr double kStep = 0.5;       // metres between frames

/// Adds a grid on a plane spanned by `origin + s * du + t * dv`, wound so that its normal
/// points to `towards`.
void addGrid(vdbmap::TriMesh& mesh, const Vec3f& origin, const Vec3f& du, const Vec3f& dv, int nu,
             int nv, const Vec3f& towards) {
    std::vector<vdbmap::TriMesh::VertexHandle> vh;
    vh.reserve(static_cast<std::size_t>(nu + 1) * (nv + 1));
    for (int j = 0; j <= nv; ++j) {
        for (int i = 0; i <= nu; ++i) {
            const Vec3f p = origin + du * (float(i) / nu) + dv * (float(j) / nv);
            vh.push_back(mesh.add_vertex({p.x(), p.y(), p.z()}));
        }
    }
    const bool flip = du.cross(dv).dot(towards) < 0;
    auto id = [&](int i, int j) { return vh[static_cast<std::size_t>(j) * (nu + 1) + i]; };
    for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
            if (!flip) {
                mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
                mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
            } else {
                mesh.add_face(id(i, j), id(i + 1, j + 1), id(i + 1, j));
                mesh.add_face(id(i, j), id(i, j + 1), id(i + 1, j + 1));
            }
        }
    }
}

cv::Vec3b pattern(double a, double b, int surface) {
    const double s = std::sin(3.1 * a) * std::cos(2.3 * b);
    const double checker = (static_cast<int>(std::floor(a)) + static_cast<int>(std::floor(b))) & 1;
    const int base = surface == 2 ? 90 : 140;
    return cv::Vec3b(cv::saturate_cast<uchar>(base + 40 * s + 30 * checker),
                     cv::saturate_cast<uchar>(base + 20 * s),
                     cv::saturate_cast<uchar>(base - 30 * s + 20 * checker));
}

/// Ray casts the canyon analytically from the camera at z = z_cam.
cv::Mat renderView(double z_cam, int width, int height, double f, double cx, double cy) {
    cv::Mat image(height, width, CV_8UC3);
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            const double dx = (u - cx) / f, dy = (v - cy) / f;
            double t = 1e9;
            int surface = -1;
            if (dx > 1e-9 && kHalfWidth / dx < t) {
                t = kHalfWidth / dx;
                surface = 0;
            }
            if (dx < -1e-9 && -kHalfWidth / dx < t) {
                t = -kHalfWidth / dx;
                surface = 1;
            }
            if (dy > 1e-9 && kGroundY / dy < t) {
                t = kGroundY / dy;
                surface = 2;
            }
            if (surface < 0) {
                image.at<cv::Vec3b>(v, u) = cv::Vec3b(230, 200, 180);  // sky
                continue;
            }
            const double x = t * dx, y = t * dy, z = z_cam + t;
            image.at<cv::Vec3b>(v, u) = surface == 2 ? pattern(x, z, 2) : pattern(z, y, surface);
        }
    }
    return image;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench_texture: texturing speed and memory on a synthetic street canyon"};
    long faces_target = 1000000;
    int num_views = 200;
    int threads = 2;
    int max_candidates = 0;
    std::string json_path;
    app.add_option("--faces", faces_target, "Approximate number of faces");
    app.add_option("--views", num_views, "Number of views (frames, one camera)");
    app.add_option("--threads", threads, "Worker threads");
    app.add_option("--json", json_path, "Write the results as JSON");
    app.add_option("--max-candidates", max_candidates, "Views per face for the MRF (0 = all)");
    CLI11_PARSE(app, argc, argv);
    try {
        tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
        const int width = 1242, height = 375;
        const double f = 720.0, cx = 620.5, cy = 187.0;
        const double length = num_views * kStep + 30.0;

        // Mesh: the two facades and the road, cells chosen to reach the face count.
        vdbmap::Timer timer;
        const double area = 2 * length * (kGroundY - kTopY) + length * 2 * kHalfWidth;
        const double cell = std::sqrt(2.0 * area / static_cast<double>(faces_target));
        const int nz = static_cast<int>(std::ceil(length / cell));
        const int ny = static_cast<int>(std::ceil((kGroundY - kTopY) / cell));
        const int nx = static_cast<int>(std::ceil(2 * kHalfWidth / cell));
        vdbmap::TriMesh mesh;
        const float L = static_cast<float>(length);
        addGrid(mesh, Vec3f(-kHalfWidth, kTopY, 0), Vec3f(0, 0, L), Vec3f(0, kGroundY - kTopY, 0),
                nz, ny, Vec3f(1, 0, 0));
        addGrid(mesh, Vec3f(kHalfWidth, kTopY, 0), Vec3f(0, 0, L), Vec3f(0, kGroundY - kTopY, 0),
                nz, ny, Vec3f(-1, 0, 0));
        addGrid(mesh, Vec3f(-kHalfWidth, kGroundY, 0), Vec3f(0, 0, L), Vec3f(2 * kHalfWidth, 0, 0),
                nz, nx, Vec3f(0, -1, 0));
        mesh.request_face_normals();
        mesh.update_face_normals();
        const double mesh_s = timer.elapsedSeconds();

        // Views and their PNG-encoded images.
        timer.reset();
        std::vector<vdbmap::View> views(num_views);
        std::vector<std::vector<uchar>> png(num_views);
        tbb::parallel_for(0, num_views, [&](int i) {
            vdbmap::View& view = views[i];
            view.frame = i;
            view.camera = 0;
            view.intrinsics.width = width;
            view.intrinsics.height = height;
            view.intrinsics.fx = view.intrinsics.fy = f;
            view.intrinsics.cx = cx;
            view.intrinsics.cy = cy;
            view.T_C_W = vdbmap::Isometry3d::Identity();
            view.T_C_W.translation() = vdbmap::Vec3d(0, 0, -kStep * i);
            cv::imencode(".png", renderView(kStep * i, width, height, f, cx, cy), png[i]);
        });
        const double images_s = timer.elapsedSeconds();

        timer.reset();
        const vdbmap::Raycaster raycaster = vdbmap::Raycaster::fromMesh(mesh);
        const vdbmap::Visibility vis =
            vdbmap::computeVisibility(mesh, views, vdbmap::VisibilityOptions{}, &raycaster);
        const auto adjacency = vdbmap::faceAdjacency(mesh);
        const double visibility_s = timer.elapsedSeconds();
        const std::size_t visibility_mem = vdbmap::peakMemoryBytes();

        const vdbmap::texture::MeshArrays arrays = vdbmap::texture::meshArrays(mesh);
        const vdbmap::texture::ImageLoader load = [&](std::size_t v) {
            return cv::imdecode(png[v], cv::IMREAD_COLOR);
        };
        vdbmap::texture::TextureOptions options;
        options.vignetting = true;
        options.vignetting_params = {{0.3, 0.1, 0.05}};
        options.max_candidates = static_cast<std::size_t>(max_candidates);
        timer.reset();
        const auto result =
            vdbmap::texture::textureMesh(arrays, views, vis, adjacency, load, options);
        const double texture_s = timer.elapsedSeconds();

        nlohmann::json out;
        out["faces"] = arrays.faces.size();
        out["views"] = num_views;
        out["threads"] = threads;
        out["max_candidates"] = max_candidates;
        out["observations"] = vis.obs.size();
        out["untextured"] = result.stats.faces_untextured;
        out["patches"] = result.stats.patches;
        out["atlas_pages"] = result.stats.pages;
        out["setup_s"] = {{"mesh", mesh_s}, {"render_encode_images", images_s}};
        out["timings_s"]["visibility_and_adjacency"] = visibility_s;
        out["peak_memory_mib"]["visibility_and_adjacency"] = visibility_mem / 1048576.0;
        for (const auto& [step, s] : result.stats.timings_s) out["timings_s"][step] = s;
        for (const auto& [step, b] : result.stats.peak_memory_bytes) {
            out["peak_memory_mib"][step] = b / 1048576.0;
        }
        const double total = visibility_s + texture_s;
        out["timings_s"]["total_texturing"] = total;
        out["faces_per_s"] = arrays.faces.size() / total;
        std::cout << out.dump(2) << std::endl;
        if (!json_path.empty()) std::ofstream(json_path) << out.dump(2) << "\n";
    } catch (const std::exception& e) {
        std::cerr << "bench_texture: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
