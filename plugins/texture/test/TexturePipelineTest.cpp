// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "ObjExport.h"
#include "TexturePipeline.h"
#include "TextureTestScenes.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/mrf/PottsMrf.h"

using namespace vdbmap::texture;
using namespace vdbmap::texture::test;
using vdbmap::Vec3f;

namespace {

constexpr float kDepth = 5.0f;

/// Ground-truth colour of the plane z = kDepth at world (x, y), BGR.
Vec3f planeColor(double x, double y) {
    return Vec3f(static_cast<float>(100 + 40 * std::sin(3 * x)),
                 static_cast<float>(120 + 30 * std::cos(4 * y)),
                 static_cast<float>(90 + 20 * std::sin(2 * x + y)));
}

/// Renders the plane into a view, adding `offset` to every channel and dividing by the
/// vignetting gain `vignette` (the camera darkens its border).
cv::Mat renderPlane(const vdbmap::View& view, float offset, const VignettingParams& vignette) {
    const auto& in = view.intrinsics;
    cv::Mat image(in.height, in.width, CV_8UC3);
    const double centre_x = -view.T_C_W.translation().x();
    for (int v = 0; v < in.height; ++v) {
        for (int u = 0; u < in.width; ++u) {
            const double x = (u - in.cx) / in.fx * kDepth + centre_x;
            const double y = (v - in.cy) / in.fy * kDepth;
            const double g = vignettingGain(
                vignette, vignettingRadius(u, v, (in.width - 1) / 2.0, (in.height - 1) / 2.0));
            const Vec3f c = (planeColor(x, y) + Vec3f::Constant(offset)) / static_cast<float>(g);
            image.at<cv::Vec3b>(v, u) =
                cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                          cv::saturate_cast<uchar>(c[2]));
        }
    }
    return image;
}

Vec3f sampleAtlas(const cv::Mat& page, const Eigen::Vector2f& uv) {
    const float X = uv.x() * page.cols - 0.5f, Y = (1.0f - uv.y()) * page.rows - 0.5f;
    const int x = std::clamp(static_cast<int>(std::lround(X)), 0, page.cols - 1);
    const int y = std::clamp(static_cast<int>(std::lround(Y)), 0, page.rows - 1);
    const cv::Vec3b c = page.at<cv::Vec3b>(y, x);
    return Vec3f(c[0], c[1], c[2]);
}

struct TwoViewScene {
    MeshArrays mesh = planeGrid(16, 8, 2.0f, 1.0f, kDepth);
    std::vector<vdbmap::View> views = {makeView(0, -0.3), makeView(1, 0.3)};
    vdbmap::Visibility vis;
    std::vector<std::array<std::uint32_t, 2>> adjacency = bruteAdjacency(mesh);
    std::vector<cv::Mat> images;

    TwoViewScene(float offset_view1, const VignettingParams& vignette, bool hide_face0) {
        // Left half seen by view 0 only, right half by view 1 only: two patches, one seam.
        vis = makeVisibility(mesh, views, [&](std::size_t f, std::uint32_t v) {
            if (hide_face0 && f == 0) return false;
            return (centroidX(f) < 0) == (v == 0);
        });
        images = {renderPlane(views[0], 0.0f, vignette),
                  renderPlane(views[1], offset_view1, vignette)};
    }
    float centroidX(std::size_t f) const {
        float x = 0;
        for (auto v : mesh.faces[f]) x += mesh.vertices_W[v].x();
        return x / 3.0f;
    }
    Eigen::Vector2f centroidXY(std::size_t f) const {
        Eigen::Vector2f c = Eigen::Vector2f::Zero();
        for (auto v : mesh.faces[f]) c += mesh.vertices_W[v].head<2>();
        return c / 3.0f;
    }
    TextureResult run(const TextureOptions& options) const {
        const ImageLoader load = [this](std::size_t v) { return images[v].clone(); };
        return textureMesh(mesh, views, vis, adjacency, load, options);
    }
    /// Mean texture error (atlas colour at the face centroid minus the truth) of the faces
    /// left and right of the seam, averaged over channels.
    std::pair<double, double> sideErrors(const TextureResult& result) const {
        double left = 0, right = 0;
        int nl = 0, nr = 0;
        for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
            if (result.face_view[f] == vdbmap::kNoLabel) continue;
            const Eigen::Vector2f uv =
                (result.face_uvs[f][0] + result.face_uvs[f][1] + result.face_uvs[f][2]) / 3.0f;
            const Vec3f c = sampleAtlas(result.pages[result.face_page[f]], uv);
            const Eigen::Vector2f p = centroidXY(f);
            const double e = (c - planeColor(p.x(), p.y())).mean();
            if (centroidX(f) < 0) {
                left += e;
                ++nl;
            } else {
                right += e;
                ++nr;
            }
        }
        return {left / nl, right / nr};
    }
};

TextureOptions baseOptions() {
    TextureOptions options;
    options.use_mrf = true;
    options.lambda = 1.0;
    options.photo_consistency = false;
    options.global_adjustment = false;
    return options;
}

}  // namespace

TEST_CASE("best-view texture reproduces the plane's colours", "[texture]") {
    const TwoViewScene scene(0.0f, {}, false);
    const TextureResult result = scene.run(baseOptions());
    CHECK(result.stats.faces_untextured == 0);
    CHECK(result.stats.patches == 2);
    CHECK(result.pages.size() == 1);
    const auto [left, right] = scene.sideErrors(result);
    CHECK(std::abs(left) < 2.0);
    CHECK(std::abs(right) < 2.0);
}

TEST_CASE("global adjustment removes a known offset between two views", "[texture]") {
    const float offset = 24.0f;
    const TwoViewScene scene(offset, {}, false);
    const TextureResult plain = scene.run(baseOptions());
    const auto [l0, r0] = scene.sideErrors(plain);
    CHECK((r0 - l0) == Approx(offset).margin(2.0));

    TextureOptions options = baseOptions();
    options.global_adjustment = true;
    options.leveling.space = SeamSpace::kBgr;  // an offset is levelled exactly as an offset
    const TextureResult leveled = scene.run(options);
    CHECK(leveled.stats.seam_edges > 0);
    const auto [l1, r1] = scene.sideErrors(leveled);
    // The seam disappears: both sides move half way (smallest correction).
    CHECK(std::abs(r1 - l1) < 2.0);
    CHECK(l1 == Approx(offset / 2).margin(3.0));
}

TEST_CASE("vignetting correction in the pipeline restores the colours", "[texture]") {
    const VignettingParams vignette{1.5, 0.5, 0.5};
    const TwoViewScene scene(0.0f, vignette, false);
    const TextureResult raw = scene.run(baseOptions());
    TextureOptions options = baseOptions();
    options.vignetting = true;
    options.vignetting_params = {vignette};
    const TextureResult corrected = scene.run(options);
    const auto [lr, rr] = scene.sideErrors(raw);
    const auto [lc, rc] = scene.sideErrors(corrected);
    CHECK(lr < -3.0);  // darkened borders
    CHECK(std::abs(lc) < 2.0);
    CHECK(std::abs(rc) < 2.0);
}

TEST_CASE("textured OBJ, MTL and atlas PNG load back with UVs inside the atlas", "[texture][io]") {
    const TwoViewScene scene(10.0f, {}, true);
    TextureOptions options = baseOptions();
    options.global_adjustment = true;
    options.photo_consistency = true;
    const TextureResult result = scene.run(options);
    CHECK(result.stats.faces_untextured == 1);
    // The unseen face takes the colour of its textured neighbours (quantised to 17 levels).
    const Eigen::Vector2f uv0 = result.face_uvs[0][0];
    const Vec3f fill = sampleAtlas(result.pages[result.face_page[0]], uv0);
    const Eigen::Vector2f c0 = scene.centroidXY(0);
    CHECK((fill - planeColor(c0.x(), c0.y())).cwiseAbs().maxCoeff() < 16.0f);
    CHECK(fill != Vec3f(128, 128, 128));
    TextureOptions grey_options = options;
    grey_options.fill_from_neighbours = false;
    const TextureResult grey = scene.run(grey_options);
    CHECK(sampleAtlas(grey.pages[grey.face_page[0]], grey.face_uvs[0][0]) == Vec3f(128, 128, 128));

    const auto dir = std::filesystem::temp_directory_path() / "vdbmap_texture_pipeline_test";
    std::filesystem::remove_all(dir);
    writeTexturedMesh(dir, scene.mesh, result);
    const vdbmap::ObjMesh obj = vdbmap::readObj(dir / "mesh.obj");
    REQUIRE(obj.triangles.size() == scene.mesh.faces.size());
    REQUIRE(obj.positions.size() == scene.mesh.vertices_W.size());
    REQUIRE(obj.uvs.size() == 3 * scene.mesh.faces.size());
    REQUIRE(obj.materials.size() == result.pages.size());
    for (const auto& uv : obj.uvs) {
        CHECK(uv.x() >= 0.0f);
        CHECK(uv.x() <= 1.0f);
        CHECK(uv.y() >= 0.0f);
        CHECK(uv.y() <= 1.0f);
    }
    for (std::size_t p = 0; p < obj.materials.size(); ++p) {
        const auto& material = obj.materials[p];
        CHECK(std::filesystem::path(material.texture).is_relative());
        const cv::Mat png = cv::imread((dir / material.texture).string(), cv::IMREAD_COLOR);
        REQUIRE_FALSE(png.empty());
        CHECK(png.cols == result.pages[p].cols);
        CHECK(png.rows == result.pages[p].rows);
        CHECK(png.cols <= 8192);
        CHECK(png.rows <= 8192);
    }
    // UVs read back equal what was written (OBJ keeps 6 decimals).
    for (std::size_t f = 0; f < scene.mesh.faces.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const auto& uv = obj.uvs[obj.triangles[f].vt[k]];
            CHECK(uv.x() == Approx(result.face_uvs[f][k].x()).margin(1e-5));
            CHECK(uv.y() == Approx(result.face_uvs[f][k].y()).margin(1e-5));
        }
    }
    std::filesystem::remove_all(dir);
}

TEST_CASE("texturing rejects inconsistent inputs", "[texture]") {
    TwoViewScene scene(0.0f, {}, false);
    scene.vis.offsets.pop_back();
    CHECK_THROWS_AS(scene.run(baseOptions()), vdbmap::InvalidInput);
    TwoViewScene wrong_size(0.0f, {}, false);
    wrong_size.images[1] = cv::Mat(10, 10, CV_8UC3, cv::Scalar(0, 0, 0));
    CHECK_THROWS_AS(wrong_size.run(baseOptions()), vdbmap::InvalidInput);
}
