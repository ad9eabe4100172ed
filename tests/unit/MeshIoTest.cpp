// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/MeshIO.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

namespace {

/// A unit cube's 8 vertices and 12 triangles, normals pointing out from the centre.
TriMesh cube() {
    TriMesh mesh;
    std::vector<TriMesh::VertexHandle> v;
    for (int i = 0; i < 8; ++i) {
        v.push_back(mesh.add_vertex(TriMesh::Point(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
    }
    const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                              {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& f : faces) mesh.add_face(v[f[0]], v[f[1]], v[f[2]]);
    for (const auto vh : mesh.vertices()) {
        mesh.set_normal(vh, (mesh.point(vh) - TriMesh::Point(0.5f, 0.5f, 0.5f)).normalized());
    }
    return mesh;
}

}  // namespace

TEST_CASE("Binary PLY mesh round trip: positions, normals, labels, colours", "[io][ply]") {
    test::TempDir dir;
    const TriMesh mesh = cube();
    REQUIRE(mesh.n_faces() == 12);
    std::vector<std::uint8_t> labels;
    std::vector<std::array<std::uint8_t, 3>> colors;
    for (std::uint8_t f = 0; f < 12; ++f) {
        labels.push_back(f == 11 ? 255 : f);
        colors.push_back({f, static_cast<std::uint8_t>(2 * f), 7});
    }
    std::vector<std::array<std::uint8_t, 3>> vertex_colors(8, {1, 2, 3});
    PlyWriteOptions options;
    options.face_labels = &labels;
    options.face_colors = &colors;
    options.vertex_colors = &vertex_colors;
    writeMeshPly(dir / "semantic" / "mesh.ply", mesh, options);

    const std::string bytes = test::readBytes(dir / "semantic" / "mesh.ply");
    CHECK_THAT(bytes.substr(0, 200), Contains("format binary_little_endian 1.0"));
    CHECK_THAT(bytes, Contains("property list uchar int vertex_indices\nproperty uchar label\n"
                               "property uchar red"));

    std::vector<std::uint8_t> labels_back;
    const TriMesh back = readMeshPly(dir / "semantic" / "mesh.ply", &labels_back);
    REQUIRE(back.n_vertices() == 8);
    REQUIRE(back.n_faces() == 12);
    CHECK(labels_back == labels);
    for (const auto vh : back.vertices()) {
        const auto& p = back.point(vh);
        CHECK(p == mesh.point(TriMesh::VertexHandle(vh.idx())));
        CHECK(back.normal(vh) == mesh.normal(TriMesh::VertexHandle(vh.idx())));
    }
    for (const auto fh : back.faces()) {
        auto it = back.cfv_iter(fh);
        auto jt = mesh.cfv_iter(TriMesh::FaceHandle(fh.idx()));
        for (int k = 0; k < 3; ++k, ++it, ++jt) CHECK(it->idx() == jt->idx());
    }
    CHECK(test::countEntries(dir / "semantic") == 1);
}

TEST_CASE("PLY mesh: deleted faces are skipped, size mismatches rejected", "[io][ply]") {
    test::TempDir dir;
    TriMesh mesh = cube();
    mesh.delete_face(TriMesh::FaceHandle(0), false);
    writeMeshPly(dir / "mesh.ply", mesh);
    CHECK(readMeshPly(dir / "mesh.ply").n_faces() == 11);
    const std::vector<std::uint8_t> short_labels(3, 0);
    PlyWriteOptions options;
    options.face_labels = &short_labels;
    CHECK_THROWS_AS(writeMeshPly(dir / "bad.ply", mesh, options), InvalidInput);
    CHECK_FALSE(std::filesystem::exists(dir / "bad.ply"));
}

TEST_CASE("ASCII PLY with a quad and extra properties reads as triangles", "[io][ply]") {
    test::TempDir dir;
    test::writeText(dir / "quad.ply",
                    "ply\nformat ascii 1.0\ncomment hand written\nelement vertex 4\n"
                    "property float x\nproperty float y\nproperty float z\nproperty float "
                    "confidence\nelement face 1\nproperty list uchar int vertex_index\n"
                    "property uchar label\nend_header\n0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n"
                    "4 0 1 2 3 13\n");
    std::vector<std::uint8_t> labels;
    const TriMesh mesh = readMeshPly(dir / "quad.ply", &labels);
    CHECK(mesh.n_vertices() == 4);
    CHECK(mesh.n_faces() == 2);
    CHECK(labels == std::vector<std::uint8_t>{13, 13});

    test::writeText(dir / "bad.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty floot x\n"
                    "end_header\n0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readMeshPly(dir / "bad.ply"); }),
               Contains("bad.ply:4") && Contains("floot"));
    test::writeText(dir / "short.ply",
                    "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\n0 0 0\n1\n");
    CHECK_THAT(test::ioErrorMessage([&] { readMeshPly(dir / "short.ply"); }),
               Contains("short.ply"));
}
