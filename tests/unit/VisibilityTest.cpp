// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <tbb/global_control.h>

#include <cmath>
#include <random>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/Visibility.h"

using vdbmap::TriMesh;
using vdbmap::Vec3d;
using vdbmap::View;

namespace {

// Square grid of quads (two triangles each) in the plane z = height, normals +z.
void addGrid(TriMesh& mesh, double half_size_m, double cell_m, double height) {
    const int n = static_cast<int>(std::lround(2.0 * half_size_m / cell_m));
    std::vector<TriMesh::VertexHandle> v;
    for (int y = 0; y <= n; ++y) {
        for (int x = 0; x <= n; ++x) {
            v.push_back(mesh.add_vertex(TriMesh::Point(float(-half_size_m + x * cell_m),
                                                       float(-half_size_m + y * cell_m),
                                                       float(height))));
        }
    }
    auto at = [&](int x, int y) { return v[static_cast<std::size_t>(y * (n + 1) + x)]; };
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            mesh.add_face(at(x, y), at(x + 1, y), at(x + 1, y + 1));
            mesh.add_face(at(x, y), at(x + 1, y + 1), at(x, y + 1));
        }
    }
}

// A 640 x 480 camera with f = 500 px at `centre_W`, looking straight down (-z); image x is
// world +x and image y is world -y.
View downView(const Vec3d& centre_W) {
    View view;
    view.intrinsics.width = 640;
    view.intrinsics.height = 480;
    view.intrinsics.fx = view.intrinsics.fy = 500.0;
    view.intrinsics.cx = 319.5;
    view.intrinsics.cy = 239.5;
    vdbmap::Isometry3d T_W_C = vdbmap::Isometry3d::Identity();
    T_W_C.linear() << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    T_W_C.translation() = centre_W;
    view.T_C_W = T_W_C.inverse();
    return view;
}

// A camera at `centre_W` looking at `target_W`.
View lookAtView(const Vec3d& centre_W, const Vec3d& target_W) {
    View view = downView(centre_W);
    const Vec3d z = (target_W - centre_W).normalized();
    Vec3d x = z.cross(Vec3d::UnitZ());
    if (x.norm() < 1e-6) x = Vec3d::UnitX();
    x.normalize();
    const Vec3d y = z.cross(x);
    vdbmap::Isometry3d T_W_C = vdbmap::Isometry3d::Identity();
    T_W_C.linear().col(0) = x;
    T_W_C.linear().col(1) = y;
    T_W_C.linear().col(2) = z;
    T_W_C.translation() = centre_W;
    view.T_C_W = T_W_C.inverse();
    return view;
}

vdbmap::Vec3f corner(const TriMesh& mesh, std::size_t f, int k) {
    auto it = mesh.cfv_begin(TriMesh::FaceHandle(static_cast<int>(f)));
    for (int i = 0; i < k; ++i) ++it;
    const auto& p = mesh.point(*it);
    return {p[0], p[1], p[2]};
}

// Slow reference: every face against every view, no culling, no occlusion.
std::vector<std::vector<std::uint32_t>> referenceVisibility(
    const TriMesh& mesh, const std::vector<View>& views, const vdbmap::VisibilityOptions& opt) {
    std::vector<std::vector<std::uint32_t>> out(mesh.n_faces());
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        const vdbmap::Vec3f a = corner(mesh, f, 0), b = corner(mesh, f, 1), c = corner(mesh, f, 2);
        const vdbmap::Vec3f n = (b - a).cross(c - a).normalized();
        const vdbmap::Vec3f centroid = (a + b + c) / 3.0f;
        for (std::size_t v = 0; v < views.size(); ++v) {
            const Vec3d cam = views[v].T_C_W.inverse().translation();
            const vdbmap::Vec3f to_cam = cam.cast<float>() - centroid;
            const double cos_angle = n.dot(to_cam) / to_cam.norm();
            if (cos_angle <= 0.0 ||
                cos_angle < std::cos(opt.max_view_angle_deg * M_PI / 180.0)) {
                continue;
            }
            bool ok = true;
            for (const vdbmap::Vec3f& p : {a, b, c}) {
                const Vec3d p_C = views[v].T_C_W * p.cast<double>();
                vdbmap::Vec2d px;
                ok = ok && p_C.z() >= opt.min_depth_m && p_C.z() <= opt.max_depth_m &&
                     views[v].intrinsics.project(p_C, px) && views[v].intrinsics.inside(px);
            }
            if (ok) out[f].push_back(static_cast<std::uint32_t>(v));
        }
    }
    return out;
}

}  // namespace

TEST_CASE("a fronto-parallel plane is visible exactly inside the image", "[visibility]") {
    TriMesh mesh;
    addGrid(mesh, 4.0, 0.25, 0.0);
    const std::vector<View> views{downView({0, 0, 5})};
    const auto vis = vdbmap::computeVisibility(mesh, views, {}, nullptr);
    REQUIRE(vis.numFaces() == mesh.n_faces());
    std::size_t expected = 0;
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        // u = 319.5 + 100 x and v = 239.5 - 100 y at depth 5 m.
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
            const auto p = corner(mesh, f, k);
            inside = inside && p.x() >= -3.2f && p.x() < 3.2f && p.y() > -2.4f && p.y() <= 2.4f;
        }
        expected += inside;
        REQUIRE(vis.count(f) == (inside ? 1u : 0u));
        if (!inside) continue;
        const auto& obs = *vis.begin(f);
        REQUIRE(obs.view == 0);
        REQUIRE(obs.depth_m == Approx(5.0));
        // Orthographic at constant depth: 0.03125 m^2 * (100 px/m)^2.
        REQUIRE(obs.area_px == Approx(312.5).epsilon(1e-4));
        const auto c = corner(mesh, f, 0);
        REQUIRE(obs.pixels[0].x() == Approx(319.5 + 100.0 * c.x()).margin(1e-3));
        REQUIRE(obs.pixels[0].y() == Approx(239.5 - 100.0 * c.y()).margin(1e-3));
    }
    REQUIRE(expected == 864);  // 24 x 18 quads of 0.25 m
}

TEST_CASE("back faces, grazing views and out-of-range depths are not visible", "[visibility]") {
    TriMesh mesh;
    addGrid(mesh, 2.0, 0.5, 0.0);
    SECTION("camera below the plane") {
        View below = downView({0, 0, -5});
        below.T_C_W = lookAtView({0, 0, -5}, {0, 0, 0}).T_C_W;
        const auto vis = vdbmap::computeVisibility(mesh, {below}, {}, nullptr);
        REQUIRE(vis.obs.empty());
    }
    SECTION("max view angle") {
        // Camera 1 m above the plane, 10 m away: about 84 degrees from the normal.
        const View grazing = lookAtView({10, 0, 1}, {0, 0, 0});
        vdbmap::VisibilityOptions opt;
        opt.max_view_angle_deg = 80.0;
        REQUIRE(vdbmap::computeVisibility(mesh, {grazing}, opt, nullptr).obs.empty());
        opt.max_view_angle_deg = 89.0;
        REQUIRE(!vdbmap::computeVisibility(mesh, {grazing}, opt, nullptr).obs.empty());
    }
    SECTION("depth range") {
        vdbmap::VisibilityOptions opt;
        opt.max_depth_m = 4.0;
        REQUIRE(vdbmap::computeVisibility(mesh, {downView({0, 0, 5})}, opt, nullptr)
                    .obs.empty());
        opt.max_depth_m = 6.0;
        opt.min_depth_m = 5.5;
        REQUIRE(vdbmap::computeVisibility(mesh, {downView({0, 0, 5})}, opt, nullptr)
                    .obs.empty());
    }
}

TEST_CASE("an occluder hides the faces behind it", "[visibility]") {
    TriMesh mesh;
    addGrid(mesh, 2.0, 0.25, 0.0);  // fully inside the image
    const std::size_t ground_faces = mesh.n_faces();
    addGrid(mesh, 0.5, 0.25, 1.0);  // 1 m x 1 m roof at height 1 m
    const auto raycaster = vdbmap::Raycaster::fromMesh(mesh);
    const std::vector<View> views{downView({0, 0, 5})};
    const auto without = vdbmap::computeVisibility(mesh, views, {}, nullptr);
    const auto with = vdbmap::computeVisibility(mesh, views, {}, &raycaster);
    std::size_t hidden = 0;
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        REQUIRE(without.count(f) == 1);
        const vdbmap::Vec3f c =
            (corner(mesh, f, 0) + corner(mesh, f, 1) + corner(mesh, f, 2)) / 3.0f;
        if (f >= ground_faces) {
            REQUIRE(with.count(f) == 1);  // the roof itself
            continue;
        }
        // The roof's shadow from the camera at 5 m covers |x|, |y| < 0.625 on the ground.
        const float r = std::max(std::abs(c.x()), std::abs(c.y()));
        if (r < 0.5f) REQUIRE(with.count(f) == 0);
        if (r > 0.75f) REQUIRE(with.count(f) == 1);
        hidden += with.count(f) == 0;
    }
    REQUIRE(hidden >= 32);  // at least the 4 x 4 quads right under the roof
}

TEST_CASE("culling and the CSR agree with a brute-force reference, for any thread count",
          "[visibility]") {
    TriMesh mesh;
    addGrid(mesh, 6.0, 0.4, 0.0);
    addGrid(mesh, 1.0, 0.5, 2.0);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> pos(-12.0, 12.0);
    std::uniform_real_distribution<double> height(0.5, 12.0);
    std::uniform_real_distribution<double> target(-3.0, 3.0);
    std::vector<View> views;
    for (int v = 0; v < 40; ++v) {
        views.push_back(lookAtView({pos(rng), pos(rng), height(rng)}, {target(rng), target(rng), 0}));
    }
    vdbmap::VisibilityOptions opt;
    opt.max_view_angle_deg = 75.0;
    opt.max_depth_m = 15.0;
    const auto reference = referenceVisibility(mesh, views, opt);
    vdbmap::Visibility one_thread;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one_thread = vdbmap::computeVisibility(mesh, views, opt, nullptr);
    }
    const auto parallel = vdbmap::computeVisibility(mesh, views, opt, nullptr);
    REQUIRE(parallel.offsets == one_thread.offsets);
    std::size_t total = 0;
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        std::vector<std::uint32_t> got;
        for (auto it = parallel.begin(f); it != parallel.end(f); ++it) got.push_back(it->view);
        REQUIRE(got == reference[f]);  // same set, sorted by view
        total += got.size();
        for (std::size_t k = 0; k < got.size(); ++k) {
            REQUIRE(one_thread.begin(f)[k].area_px == parallel.begin(f)[k].area_px);
        }
    }
    REQUIRE(total > 1000);
}

TEST_CASE("bad visibility options are rejected", "[visibility]") {
    TriMesh mesh;
    addGrid(mesh, 1.0, 0.5, 0.0);
    vdbmap::VisibilityOptions opt;
    opt.max_view_angle_deg = 120.0;
    REQUIRE_THROWS_WITH(vdbmap::computeVisibility(mesh, {downView({0, 0, 5})}, opt, nullptr),
                        Catch::Contains("max_view_angle_deg") && Catch::Contains("120"));
    View broken = downView({0, 0, 5});
    broken.intrinsics.width = 0;
    REQUIRE_THROWS_AS(vdbmap::computeVisibility(mesh, {broken}, {}, nullptr),
                      vdbmap::InvalidInput);
    // Empty inputs are no-ops.
    REQUIRE(vdbmap::computeVisibility(TriMesh(), {downView({0, 0, 5})}, {}, nullptr)
                .numFaces() == 0);
    REQUIRE(vdbmap::computeVisibility(mesh, {}, {}, nullptr).obs.empty());
}
