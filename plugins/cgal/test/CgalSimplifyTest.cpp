// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "MeshSimplify.h"
#include "vdbmap/Error.h"

using vdbmap::TriMesh;

namespace {

/// A flat n x n grid of squares (2 n^2 triangles) in the plane z = z0.
TriMesh makeGrid(int n, float z0) {
    TriMesh mesh;
    std::vector<TriMesh::VertexHandle> v;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            v.push_back(mesh.add_vertex(TriMesh::Point(0.1f * i, 0.1f * j, z0)));
        }
    }
    auto at = [&](int i, int j) { return v[static_cast<std::size_t>(j * (n + 1) + i)]; };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
    return mesh;
}

/// A UV sphere of radius r.
TriMesh makeSphere(float r, int rings, int sectors) {
    TriMesh mesh;
    std::vector<TriMesh::VertexHandle> v;
    const auto top = mesh.add_vertex(TriMesh::Point(0, 0, r));
    for (int i = 1; i < rings; ++i) {
        const double theta = M_PI * i / rings;
        for (int j = 0; j < sectors; ++j) {
            const double phi = 2 * M_PI * j / sectors;
            v.push_back(mesh.add_vertex(TriMesh::Point(
                static_cast<float>(r * std::sin(theta) * std::cos(phi)),
                static_cast<float>(r * std::sin(theta) * std::sin(phi)),
                static_cast<float>(r * std::cos(theta)))));
        }
    }
    const auto bottom = mesh.add_vertex(TriMesh::Point(0, 0, -r));
    auto at = [&](int ring, int s) {
        return v[static_cast<std::size_t>((ring - 1) * sectors + (s % sectors))];
    };
    for (int s = 0; s < sectors; ++s) mesh.add_face(top, at(1, s), at(1, s + 1));
    for (int ring = 1; ring < rings - 1; ++ring) {
        for (int s = 0; s < sectors; ++s) {
            mesh.add_face(at(ring, s), at(ring + 1, s), at(ring + 1, s + 1));
            mesh.add_face(at(ring, s), at(ring + 1, s + 1), at(ring, s + 1));
        }
    }
    for (int s = 0; s < sectors; ++s) mesh.add_face(bottom, at(rings - 1, s + 1), at(rings - 1, s));
    return mesh;
}

}  // namespace

TEST_CASE("a flat grid collapses to few faces that stay on the plane", "[cgal]") {
    TriMesh mesh = makeGrid(40, 0.37f);
    const auto faces_in = mesh.n_faces();
    const auto r = vdbmap::cgal::simplifyMesh(mesh, {0.05, 0.01});
    REQUIRE(r.faces_in == faces_in);
    CHECK(mesh.n_faces() == r.faces_out);
    CHECK(r.faces_out < faces_in / 5);
    CHECK(r.faces_out > 0);
    for (const auto vh : mesh.vertices()) CHECK(mesh.point(vh)[2] == Approx(0.37f).margin(1e-5));
    REQUIRE(mesh.has_vertex_normals());
}

TEST_CASE("a sphere keeps within the error bound", "[cgal]") {
    const float radius = 1.0f;
    TriMesh mesh = makeSphere(radius, 40, 80);
    const double max_error_m = 0.01;
    const auto r = vdbmap::cgal::simplifyMesh(mesh, {0.2, max_error_m});
    CHECK(r.faces_out < r.faces_in);
    // The input's vertices lie on the sphere and its chords are at most ~0.2% of r inside it,
    // so every output vertex must be within max_error_m (+ chord sag) of the sphere.
    const double sag = radius * (1.0 - std::cos(M_PI / 80));
    for (const auto vh : mesh.vertices()) {
        const auto& p = mesh.point(vh);
        const double d = std::abs(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - radius);
        CHECK(d <= max_error_m + sag + 1e-6);
    }
    // A closed input stays closed: no boundary halfedges.
    std::size_t boundary = 0;
    for (const auto heh : mesh.halfedges()) boundary += mesh.is_boundary(heh) ? 1 : 0;
    CHECK(boundary == 0);
}

TEST_CASE("bad options are rejected and an empty mesh is a no-op", "[cgal]") {
    TriMesh empty;
    CHECK(vdbmap::cgal::simplifyMesh(empty, {0.5, 0.01}).faces_out == 0);
    TriMesh mesh = makeGrid(2, 0.0f);
    CHECK_THROWS_AS(vdbmap::cgal::simplifyMesh(mesh, {0.0, 0.01}), vdbmap::InvalidInput);
    CHECK_THROWS_AS(vdbmap::cgal::simplifyMesh(mesh, {0.5, -1.0}), vdbmap::InvalidInput);
}
