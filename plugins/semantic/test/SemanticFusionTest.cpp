// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <map>
#include <random>

#include "SemanticFusion.h"
#include "SemanticTestScenes.h"
#include "SemanticVotes.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/render/Raycaster.h"

using namespace vdbmap;
using namespace vdbmap::semantic;
using vdbmap::semantic::test::addGrid;
using vdbmap::semantic::test::faceCentroid;
using vdbmap::semantic::test::lookAtView;

namespace {

cv::Mat uniformImage(std::uint8_t id) { return cv::Mat(480, 640, CV_8UC1, cv::Scalar(id)); }

}  // namespace

TEST_CASE("two disagreeing views vote with their projected areas", "[semantic]") {
    setLogLevel(LogLevel::Warn);
    const LabelSet labels = LabelSet::defaults();
    TriMesh mesh;
    addGrid(mesh, 0.5, 0.25, 0.0);
    // The near view sees each face 4x larger (half the distance) than the far view.
    const std::vector<View> views{lookAtView({0, 0, 2}, {0, 0, 0}),
                                  lookAtView({0, 0, 4}, {0, 0, 0})};
    const Visibility vis = computeVisibility(mesh, views, {}, nullptr);
    for (const std::uint8_t near_id : {std::uint8_t(1), std::uint8_t(13)}) {
        const std::uint8_t far_id = near_id == 1 ? 13 : 1;
        const FaceVotes votes = accumulateVotes(vis, {uniformImage(near_id), uniformImage(far_id)},
                                                labels);
        REQUIRE(votes.votes == 2 * mesh.n_faces());
        for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
            REQUIRE(vis.count(f) == 2);
            REQUIRE(votes.offsets[f + 1] - votes.offsets[f] == 2);
            // Weights are exactly the projected areas (px^2) of the two observations.
            const float near_area = vis.begin(f)[0].area_px;
            const float far_area = vis.begin(f)[1].area_px;
            REQUIRE(near_area == Approx(4.0f * far_area).epsilon(1e-3));
            const std::size_t k_near = near_id < far_id ? 0 : 1;
            REQUIRE(votes.weights[votes.offsets[f] + k_near] == near_area);
            REQUIRE(votes.weights[votes.offsets[f] + 1 - k_near] == far_area);
        }
        const auto result = fuseLabels(votes, faceAdjacency(mesh), labels, {});
        for (const std::uint8_t id : result.face_labels) REQUIRE(id == near_id);
        REQUIRE(result.observed_faces == mesh.n_faces());
    }
}

TEST_CASE("a view that is occluded at a face does not vote for it", "[semantic]") {
    setLogLevel(LogLevel::Warn);
    const LabelSet labels = LabelSet::defaults();
    TriMesh mesh;
    addGrid(mesh, 1.0, 0.25, 0.0);
    const std::size_t ground = mesh.n_faces();
    addGrid(mesh, 0.25, 0.25, 1.0);  // a 0.5 m roof at 1 m
    const Raycaster raycaster = Raycaster::fromMesh(mesh);
    // View 0 straight above (near, large areas) says "car" everywhere; view 1, oblique, sees
    // under the roof and says "road".
    const std::vector<View> views{lookAtView({0, 0, 3}, {0, 0, 0}),
                                  lookAtView({4, 0, 3}, {0, 0, 0})};
    const std::vector<cv::Mat> images{uniformImage(13), uniformImage(0)};
    VisibilityOptions opt;
    const auto vis_occluded = computeVisibility(mesh, views, opt, &raycaster);
    const auto vis_free = computeVisibility(mesh, views, opt, nullptr);
    FusionOptions naive;
    naive.lambda = 0.0;
    const auto with = fuseLabels(accumulateVotes(vis_occluded, images, labels),
                                 faceAdjacency(mesh), labels, naive);
    const auto without = fuseLabels(accumulateVotes(vis_free, images, labels),
                                    faceAdjacency(mesh), labels, naive);
    std::size_t under_roof = 0;
    for (std::size_t f = 0; f < ground; ++f) {
        const Vec3f c = faceCentroid(mesh, f);
        if (std::max(std::abs(c.x()), std::abs(c.y())) > 0.2f) continue;
        ++under_roof;
        REQUIRE(without.face_labels[f] == 13);  // the near view would win...
        REQUIRE(with.face_labels[f] == 0);      // ...but it cannot see the face
    }
    REQUIRE(under_roof == 8);
}

TEST_CASE("an unseen strip between two labelled regions is filled by smoothness", "[semantic]") {
    setLogLevel(LogLevel::Warn);
    const LabelSet labels = LabelSet::defaults();
    TriMesh mesh;
    addGrid(mesh, 1.0, 0.1, 0.0);
    const std::size_t plane_faces = mesh.n_faces();
    addGrid(mesh, 0.1, 0.2, 5.0);  // a separate patch no camera sees (2 faces)
    // Image: sidewalk on the left, void strip in the middle, road on the right. At 4 m,
    // u = 319.5 + 125 x.
    cv::Mat image(480, 640, CV_8UC1, cv::Scalar(255));
    image.colRange(0, 270).setTo(1);   // x < -0.4
    image.colRange(370, 640).setTo(0); // x > 0.4
    const std::vector<View> views{lookAtView({0, 0, 4}, {0, 0, 0})};
    const auto vis = computeVisibility(mesh, views, {}, nullptr);
    const FaceVotes votes = accumulateVotes(vis, {image}, labels);
    REQUIRE(votes.void_votes > 0);
    const auto adjacency = faceAdjacency(mesh);
    const auto mrf = fuseLabels(votes, adjacency, labels, {});
    FusionOptions naive;
    naive.lambda = 0.0;
    const auto argmax = fuseLabels(votes, adjacency, labels, naive);
    std::size_t strip = 0;
    for (std::size_t f = 0; f < plane_faces; ++f) {
        const Vec3f c = faceCentroid(mesh, f);
        if (std::abs(c.x()) < 0.3f) {
            ++strip;
            REQUIRE(!votes.observed(f));
            REQUIRE(argmax.face_labels[f] == kUnknownLabel);  // naive leaves a white strip
            REQUIRE((mrf.face_labels[f] == 0 || mrf.face_labels[f] == 1));
        } else if (c.x() < -0.5f) {
            REQUIRE(mrf.face_labels[f] == 1);
        } else if (c.x() > 0.5f) {
            REQUIRE(mrf.face_labels[f] == 0);
        }
    }
    REQUIRE(strip > 100);
    // The unseen patch has no observed face: unknown, counted once.
    REQUIRE(mrf.unlabelled_components == 1);
    REQUIRE(mrf.unlabelled_faces == 2);
    REQUIRE(mrf.face_labels[plane_faces] == kUnknownLabel);
    REQUIRE(mrf.face_labels[plane_faces + 1] == kUnknownLabel);
    REQUIRE(mrf.filled_faces >= strip);
    REQUIRE(mrf.final_energy <= mrf.initial_energy);
}

TEST_CASE("lambda = 0 reproduces the per-face argmax of the votes", "[semantic]") {
    setLogLevel(LogLevel::Warn);
    const LabelSet labels = LabelSet::defaults();
    TriMesh mesh;
    addGrid(mesh, 1.0, 0.1, 0.0);
    std::mt19937 rng(4);
    std::uniform_int_distribution<std::uint32_t> cls(0, static_cast<std::uint32_t>(labels.size() - 1));
    std::uniform_real_distribution<float> area(1.0f, 100.0f);
    std::uniform_int_distribution<int> count(0, 4);
    FaceVotes votes;
    votes.num_classes = labels.size();
    votes.offsets.push_back(0);
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        std::map<std::uint32_t, float> w;
        for (int k = count(rng); k > 0; --k) w[cls(rng)] += area(rng);
        for (const auto& [c, a] : w) {
            votes.classes.push_back(c);
            votes.weights.push_back(a);
        }
        votes.offsets.push_back(votes.classes.size());
    }
    FusionOptions opt;
    opt.lambda = 0.0;
    const auto result = fuseLabels(votes, faceAdjacency(mesh), labels, opt);
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        std::uint8_t expected = kUnknownLabel;
        float best = -1.0f;
        for (auto k = votes.offsets[f]; k < votes.offsets[f + 1]; ++k) {
            if (votes.weights[k] > best) {
                best = votes.weights[k];
                expected = labels.classes()[votes.classes[k]].id;
            }
        }
        REQUIRE(result.face_labels[f] == expected);
    }
    REQUIRE(result.final_energy == result.initial_energy);
    // With smoothness the energy can only go down from the argmax labelling.
    opt.lambda = 1.0;
    const auto smooth = fuseLabels(votes, faceAdjacency(mesh), labels, opt);
    REQUIRE(smooth.final_energy <= smooth.initial_energy);
}
