// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "vdbmap/mesh/MeshAdjacency.h"

namespace {

// An n x n grid of quads in the plane z = 0, two triangles per quad.
vdbmap::TriMesh gridMesh(int n) {
    vdbmap::TriMesh mesh;
    std::vector<vdbmap::TriMesh::VertexHandle> v;
    for (int y = 0; y <= n; ++y) {
        for (int x = 0; x <= n; ++x) {
            v.push_back(mesh.add_vertex(vdbmap::TriMesh::Point(float(x), float(y), 0.0f)));
        }
    }
    auto at = [&](int x, int y) { return v[static_cast<std::size_t>(y * (n + 1) + x)]; };
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            mesh.add_face(at(x, y), at(x + 1, y), at(x + 1, y + 1));
            mesh.add_face(at(x, y), at(x + 1, y + 1), at(x, y + 1));
        }
    }
    return mesh;
}

}  // namespace

TEST_CASE("faceAdjacency lists each interior edge once, sorted", "[mesh]") {
    const int n = 4;
    const auto mesh = gridMesh(n);
    const auto pairs = vdbmap::faceAdjacency(mesh);
    // Interior edges: diagonals n*n, horizontal (n-1)*n, vertical n*(n-1).
    REQUIRE(pairs.size() == static_cast<std::size_t>(n * n + 2 * n * (n - 1)));
    REQUIRE(std::is_sorted(pairs.begin(), pairs.end()));
    for (const auto& p : pairs) {
        REQUIRE(p[0] < p[1]);
        // The two faces share exactly two vertices.
        int shared = 0;
        for (auto a : mesh.fv_range(vdbmap::TriMesh::FaceHandle(static_cast<int>(p[0])))) {
            for (auto b : mesh.fv_range(vdbmap::TriMesh::FaceHandle(static_cast<int>(p[1])))) {
                shared += a == b;
            }
        }
        REQUIRE(shared == 2);
    }
}

TEST_CASE("faceAdjacency of disconnected triangles is empty", "[mesh]") {
    vdbmap::TriMesh mesh;
    for (int k = 0; k < 3; ++k) {
        const float o = 10.0f * static_cast<float>(k);
        auto a = mesh.add_vertex({o, 0, 0});
        auto b = mesh.add_vertex({o + 1, 0, 0});
        auto c = mesh.add_vertex({o, 1, 0});
        mesh.add_face(a, b, c);
    }
    REQUIRE(vdbmap::faceAdjacency(mesh).empty());
    REQUIRE(vdbmap::faceAdjacency(vdbmap::TriMesh()).empty());
}
