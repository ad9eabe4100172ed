// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/MeshIO.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

TEST_CASE("OBJ + MTL round trip: positions, UVs, materials, textures", "[io][obj]") {
    test::TempDir dir;
    ObjMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.123456789f}};
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.25f, 0.75f}};
    mesh.materials = {ObjMaterial{"atlas_0", {1, 1, 1}, "mesh_atlas_0.png"},
                      ObjMaterial{"road", {0.5f, 0.25f, 0.5f}, ""}};
    mesh.triangles.push_back({{0, 1, 2}, {0, 1, 2}, 0});
    mesh.triangles.push_back({{0, 2, 3}, {0, 2, 4}, 1});
    mesh.triangles.push_back({{1, 2, 3}, {1, 2, 3}, 0});
    writeObj(dir / "textured" / "mesh.obj", mesh);
    CHECK(std::filesystem::exists(dir / "textured" / "mesh.mtl"));
    CHECK(test::countEntries(dir / "textured") == 2);

    const ObjMesh back = readObj(dir / "textured" / "mesh.obj");
    REQUIRE(back.positions.size() == 4);
    CHECK(back.positions[3] == mesh.positions[3]);
    REQUIRE(back.uvs.size() == 5);
    CHECK(back.uvs[4] == mesh.uvs[4]);
    REQUIRE(back.materials.size() == 2);
    CHECK(back.materials[0].name == "atlas_0");
    CHECK(back.materials[0].texture == "mesh_atlas_0.png");
    CHECK(back.materials[1].diffuse == mesh.materials[1].diffuse);
    REQUIRE(back.triangles.size() == 3);
    for (std::size_t t = 0; t < 3; ++t) {
        CHECK(back.triangles[t].v == mesh.triangles[t].v);
        CHECK(back.triangles[t].vt == mesh.triangles[t].vt);
        CHECK(back.triangles[t].material == mesh.triangles[t].material);
    }
}

TEST_CASE("OBJ reader: v//vn, negative indices, polygons, errors with line", "[io][obj]") {
    test::TempDir dir;
    test::writeText(dir / "a.obj",
                    "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
                    "f 1//1 2//1 3//1 4//1\nf -4 -2 -1\n");
    const ObjMesh mesh = readObj(dir / "a.obj");
    REQUIRE(mesh.triangles.size() == 3);
    CHECK(mesh.triangles[1].v == std::array<std::uint32_t, 3>{0, 2, 3});
    CHECK(mesh.triangles[2].v == std::array<std::uint32_t, 3>{0, 2, 3});
    CHECK(mesh.materials.empty());

    test::writeText(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    CHECK_THAT(test::ioErrorMessage([&] { readObj(dir / "bad.obj"); }),
               Contains("bad.obj:3") && Contains("vertex index"));
    test::writeText(dir / "nomtl.obj", "mtllib missing.mtl\nv 0 0 0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readObj(dir / "nomtl.obj"); }), Contains("missing.mtl"));
}

TEST_CASE("OBJ reader reads the real Spot mesh with UVs", "[io][obj]") {
    const auto path =
        std::filesystem::path(VDBMAP_TEST_DATA_DIR) / "meshes" / "spot_triangulated.obj";
    if (!std::filesystem::exists(path)) return;  // data set owned by the texture tests
    const ObjMesh mesh = readObj(path);
    CHECK(mesh.positions.size() > 1000);
    CHECK(mesh.uvs.size() > 1000);
    CHECK(mesh.triangles.size() > 2000);
    for (const auto& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            REQUIRE(tri.v[k] < mesh.positions.size());
            REQUIRE(tri.vt[k] < mesh.uvs.size());
        }
    }
}
