// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "SeamLeveling.h"
#include "TextureTestScenes.h"
#include "vdbmap/Error.h"
#include "vdbmap/mrf/PottsMrf.h"

using namespace vdbmap::texture;
using namespace vdbmap::texture::test;
using vdbmap::Vec3f;

TEST_CASE("seam levelling equalises both sides of every seam", "[texture][leveling]") {
    const MeshArrays mesh = planeGrid(8, 4, 2.0f, 1.0f, 5.0f);
    const auto adjacency = bruteAdjacency(mesh);
    // Patch 0 left of x = 0, patch 1 right of it.
    std::vector<std::uint32_t> face_patch(mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        float x = 0;
        for (auto v : mesh.faces[f]) x += mesh.vertices_W[v].x();
        face_patch[f] = x < 0 ? 0 : 1;
    }
    const auto seams = findSeamEdges(mesh, face_patch, adjacency);
    REQUIRE(seams.size() == 4);  // one per grid row
    std::vector<SeamSamples> samples(seams.size());
    const Vec3f offset(30, -12, 6);
    for (std::size_t k = 0; k < seams.size(); ++k) {
        // Side b is seen brighter by `offset`, on top of a gradient along the seam.
        const Vec3f base0 = Vec3f::Constant(100.0f + 5.0f * seams[k].v0 / 9.0f);
        const Vec3f base1 = Vec3f::Constant(100.0f + 5.0f * seams[k].v1 / 9.0f);
        const bool a_left = face_patch[seams[k].face_a] == 0;
        samples[k].a_v0 = base0 + (a_left ? Vec3f::Zero() : offset);
        samples[k].a_v1 = base1 + (a_left ? Vec3f::Zero() : offset);
        samples[k].b_v0 = base0 + (a_left ? offset : Vec3f::Zero());
        samples[k].b_v1 = base1 + (a_left ? offset : Vec3f::Zero());
    }
    const auto result = solveSeamLeveling(mesh, face_patch, seams, samples, {});
    CHECK(result.seam_terms == 2 * seams.size());
    CHECK(result.unknowns == 5 * 5 + 5 * 5);
    // Every corner of patch 1 gets ~ -offset/2, patch 0 ~ +offset/2 (smallest correction).
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const Vec3f expected = face_patch[f] == 0 ? Vec3f(offset / 2) : Vec3f(-offset / 2);
            CHECK((result.corner_correction[f][k] - expected).norm() < 0.5f);
        }
    }
}

TEST_CASE("seam levelling without seams is zero; bad sizes throw", "[texture][leveling]") {
    const MeshArrays mesh = planeGrid(2, 2, 1.0f, 1.0f, 5.0f);
    const std::vector<std::uint32_t> one_patch(mesh.faces.size(), 0);
    const auto seams = findSeamEdges(mesh, one_patch, bruteAdjacency(mesh));
    CHECK(seams.empty());
    const auto result = solveSeamLeveling(mesh, one_patch, seams, {}, {});
    for (const auto& corners : result.corner_correction) {
        for (const auto& g : corners) CHECK(g.norm() == 0.0f);
    }
    CHECK_THROWS_AS(solveSeamLeveling(mesh, one_patch, {SeamEdge{}}, {}, {}), vdbmap::InvalidInput);
}
