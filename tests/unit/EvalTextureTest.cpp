// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <cmath>

#include "vdbmap/Error.h"
#include "vdbmap/eval/TextureMetrics.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/TexturedRender.h"

using namespace vdbmap;

namespace {

struct Scene {
    ObjMesh mesh;
    std::vector<cv::Mat> textures;
    std::vector<std::array<std::uint32_t, 3>> tris{{0, 1, 2}, {0, 2, 3}};
};

// A 2 m x 2 m quad at z = 3 with a 2 x 2 checker texture.
Scene texturedQuad() {
    Scene s;
    s.mesh.positions = {{-1, -1, 3}, {1, -1, 3}, {1, 1, 3}, {-1, 1, 3}};
    s.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    s.mesh.materials.push_back(ObjMaterial{});
    s.mesh.triangles = {{{0, 1, 2}, {0, 1, 2}, 0}, {{0, 2, 3}, {0, 2, 3}, 0}};
    cv::Mat tex(64, 64, CV_8UC3, cv::Scalar(40, 80, 120));
    tex(cv::Rect(0, 0, 32, 32)).setTo(cv::Scalar(200, 150, 100));
    tex(cv::Rect(32, 32, 32, 32)).setTo(cv::Scalar(200, 150, 100));
    s.textures.push_back(tex);
    return s;
}

GtView frontView() {
    GtView v;
    v.image = "v.png";
    v.intrinsics.width = 80;
    v.intrinsics.height = 60;
    v.intrinsics.fx = v.intrinsics.fy = 40;
    v.intrinsics.cx = 39.5;
    v.intrinsics.cy = 29.5;
    return v;
}

}  // namespace

TEST_CASE("Image error: identical and constant offset", "[eval][texture]") {
    cv::Mat a(20, 30, CV_8UC3, cv::Scalar(100, 110, 120));
    TextureMetrics m;
    double sa = 0, sq = 0;
    std::size_t gt_px = 0;
    accumulateImageError(a, cv::Mat(), a, cv::Mat(), m, sa, sq, gt_px);
    finishTextureMetrics(m, sa, sq, gt_px);
    CHECK(m.mae == 0.0);
    CHECK(m.psnr_db == TextureMetrics::kMaxPsnrDb);
    CHECK(m.coverage == Approx(1.0));
    const cv::Mat b = a + cv::Scalar(10, 10, 10);
    TextureMetrics o;
    sa = sq = 0;
    gt_px = 0;
    accumulateImageError(b, cv::Mat(), a, cv::Mat(), o, sa, sq, gt_px);
    finishTextureMetrics(o, sa, sq, gt_px);
    CHECK(o.mae == Approx(10.0));
    CHECK(o.psnr_db == Approx(20.0 * std::log10(255.0 / 10.0)));
    CHECK_THROWS_AS(accumulateImageError(cv::Mat(5, 5, CV_8UC3), cv::Mat(), a, cv::Mat(), o, sa,
                                         sq, gt_px),
                    InvalidInput);
}

TEST_CASE("Rendering the ground truth itself scores perfectly", "[eval][texture]") {
    const Scene s = texturedQuad();
    const Raycaster rc(s.mesh.positions, s.tris);
    const GtView view = frontView();
    const RenderedView gt_render =
        renderView({RenderLayer{&s.mesh, &s.textures, &rc, nullptr}}, view.intrinsics,
                   view.T_W_C.inverse());
    const int surface = cv::countNonZero(gt_render.face >= 0);
    // The quad spans +-1 m at 3 m: 2 m / 3 m * 40 px = 26.7 px wide and high.
    CHECK(surface == Approx(26.67 * 26.67).epsilon(0.06));
    const TextureMetrics same = evaluateTexture(s.mesh, s.textures, {view}, {gt_render.color}, &rc);
    CHECK(same.psnr_db == TextureMetrics::kMaxPsnrDb);
    CHECK(same.mae == 0.0);
    CHECK(same.coverage == Approx(1.0));
    // A prediction 5 grey levels too bright everywhere: MAE 5.
    Scene brighter = s;
    brighter.textures[0] = cv::Mat(s.textures[0] + cv::Scalar(5, 5, 5));  // new buffer
    const TextureMetrics off =
        evaluateTexture(brighter.mesh, brighter.textures, {view}, {gt_render.color}, &rc);
    CHECK(off.mae == Approx(5.0).margin(0.05));
    // Half the quad missing from the prediction: coverage ~ 0.5.
    Scene half = s;
    half.mesh.positions = {{-1, -1, 3}, {0, -1, 3}, {0, 1, 3}, {-1, 1, 3}};
    half.mesh.uvs = {{0, 0}, {0.5f, 0}, {0.5f, 1}, {0, 1}};
    const TextureMetrics h = evaluateTexture(half.mesh, half.textures, {view}, {gt_render.color}, &rc);
    CHECK(h.coverage == Approx(0.5).margin(0.03));
    CHECK(h.mae == Approx(0.0).margin(0.5));
}
