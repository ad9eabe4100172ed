// SPDX-License-Identifier: Apache-2.0
// A view does not texture a face that touches a masked pixel of its image
// (texture.mrf `image_masks`, vdbmap/render/ImageMasks.h).
#include <catch2/catch.hpp>
#include <cmath>

#include "TexturePipeline.h"
#include "TextureTestScenes.h"
#include "vdbmap/Error.h"
#include "vdbmap/mrf/PottsMrf.h"
#include "vdbmap/render/ImageMasks.h"

using namespace vdbmap::texture;
using namespace vdbmap::texture::test;

namespace {

/// Slow reference: is any of the observation's four samples (centroid, corners pulled 30 %
/// towards it) within `r` pixels (Chebyshev) of a non-zero mask pixel? Scans the whole mask.
bool referenceMasked(const vdbmap::FaceObservation& o, const cv::Mat& mask, int r) {
    const Eigen::Vector2f c = (o.pixels[0] + o.pixels[1] + o.pixels[2]) / 3.0f;
    const Eigen::Vector2f samples[4] = {c, c + 0.7f * (o.pixels[0] - c),
                                        c + 0.7f * (o.pixels[1] - c), c + 0.7f * (o.pixels[2] - c)};
    for (const auto& s : samples) {
        const long sx = std::lround(s.x()), sy = std::lround(s.y());
        if (sx < 0 || sy < 0 || sx >= mask.cols || sy >= mask.rows) continue;
        for (int y = 0; y < mask.rows; ++y) {
            for (int x = 0; x < mask.cols; ++x) {
                if (mask.at<std::uint8_t>(y, x) && std::abs(x - sx) <= r && std::abs(y - sy) <= r) {
                    return true;
                }
            }
        }
    }
    return false;
}

/// Image columns [u0, u1) of every row masked, e.g. a car a detector found.
cv::Mat columnMask(const vdbmap::View& view, int u0, int u1) {
    cv::Mat mask(view.intrinsics.height, view.intrinsics.width, CV_8UC1, cv::Scalar(0));
    mask.colRange(u0, u1).setTo(255);
    return mask;
}

}  // namespace

TEST_CASE("image masks remove exactly the observations a slow reference finds masked",
          "[texture][image_masks]") {
    const MeshArrays mesh = planeGrid(16, 8, 2.0f, 1.0f, 5.0f);
    const std::vector<vdbmap::View> views = {makeView(0, -0.3), makeView(1, 0.3)};
    const auto all = [](std::size_t, std::uint32_t) { return true; };
    // View 0 is masked over columns 60..89, view 1 has no mask.
    const cv::Mat mask0 = columnMask(views[0], 60, 90);
    const auto masks = [&](std::size_t v) { return v == 0 ? mask0 : cv::Mat(); };
    for (const int r : {0, 2, 5}) {
        vdbmap::Visibility vis = makeVisibility(mesh, views, all);
        const vdbmap::Visibility before = vis;
        std::size_t expected = 0;
        std::vector<std::pair<std::size_t, std::uint32_t>> kept_expected;
        for (std::size_t f = 0; f < before.numFaces(); ++f) {
            for (const auto* o = before.begin(f); o != before.end(f); ++o) {
                if (o->view == 0 && referenceMasked(*o, mask0, r)) {
                    ++expected;
                } else {
                    kept_expected.emplace_back(f, o->view);
                }
            }
        }
        REQUIRE(expected > 10);
        CHECK(vdbmap::removeMaskedObservations(vis, views, masks, r) == expected);
        std::vector<std::pair<std::size_t, std::uint32_t>> kept;
        for (std::size_t f = 0; f < vis.numFaces(); ++f) {
            for (const auto* o = vis.begin(f); o != vis.end(f); ++o) kept.emplace_back(f, o->view);
        }
        CHECK(kept == kept_expected);  // the others, in their order
    }
}

TEST_CASE("a masked view does not texture the faces behind its mask", "[texture][image_masks]") {
    const MeshArrays mesh = planeGrid(16, 8, 2.0f, 1.0f, 5.0f);
    const std::vector<vdbmap::View> views = {makeView(0, -0.3), makeView(1, 0.3)};
    vdbmap::Visibility vis =
        makeVisibility(mesh, views, [](std::size_t, std::uint32_t) { return true; });
    const vdbmap::Visibility before = vis;
    // View 0's image is red where its mask is (a car the LiDAR did not see), grey elsewhere.
    const cv::Mat mask0 = columnMask(views[0], 60, 90);
    cv::Mat image0(views[0].intrinsics.height, views[0].intrinsics.width, CV_8UC3,
                   cv::Scalar(120, 120, 120));
    image0.setTo(cv::Scalar(30, 30, 220), mask0);
    const cv::Mat image1(image0.size(), CV_8UC3, cv::Scalar(120, 120, 120));
    vdbmap::removeMaskedObservations(
        vis, views, [&](std::size_t v) { return v == 0 ? mask0 : cv::Mat(); }, 2);
    TextureOptions options;
    options.use_mrf = false;  // best view per face: the masks alone decide
    options.photo_consistency = false;
    options.global_adjustment = false;
    options.exposure_gains = false;
    const TextureResult result =
        textureMesh(mesh, views, vis, bruteAdjacency(mesh),
                    [&](std::size_t v) { return v == 0 ? image0 : image1; }, options);
    std::size_t behind = 0;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto* o0 = before.begin(f);  // view 0's observation (sorted by view)
        REQUIRE(o0->view == 0);
        CHECK(result.face_view[f] != vdbmap::kNoLabel);  // view 1 sees every face
        if (referenceMasked(*o0, mask0, 2)) {
            ++behind;
            CHECK(result.face_view[f] == 1);
        }
    }
    CHECK(behind > 10);
}

TEST_CASE("image masks: bad radius or a mask of the wrong size throw", "[texture][image_masks]") {
    const MeshArrays mesh = planeGrid(4, 2, 2.0f, 1.0f, 5.0f);
    const std::vector<vdbmap::View> views = {makeView(0, 0.0)};
    vdbmap::Visibility vis =
        makeVisibility(mesh, views, [](std::size_t, std::uint32_t) { return true; });
    const auto none = [](std::size_t) { return cv::Mat(); };
    CHECK_THROWS_AS(vdbmap::removeMaskedObservations(vis, views, none, -1), vdbmap::InvalidInput);
    CHECK_THROWS_AS(vdbmap::removeMaskedObservations(vis, views, none, 33), vdbmap::InvalidInput);
    const cv::Mat small(10, 10, CV_8UC1, cv::Scalar(255));
    CHECK_THROWS_WITH(
        vdbmap::removeMaskedObservations(vis, views, [&](std::size_t) { return small; }, 0),
        Catch::Matchers::Contains("10 x 10") && Catch::Matchers::Contains("200 x 100"));
    CHECK(vis.obs.size() == mesh.faces.size());  // the failed calls removed nothing
}
