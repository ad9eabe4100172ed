// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <filesystem>

#include "LabelGrid.h"
#include "SemanticExport.h"
#include "SemanticTestScenes.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/Layers.h"

using namespace vdbmap;
using namespace vdbmap::semantic;
using vdbmap::semantic::test::addGrid;
using vdbmap::semantic::test::faceCentroid;

namespace {

std::filesystem::path scratchDir(const std::string& name) {
    const auto dir = std::filesystem::path(VDBMAP_BINARY_DIR) / "test_scratch" / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

// Left half lane marking (19), right half road (0), one unknown face.
std::vector<std::uint8_t> halfLabels(const TriMesh& mesh) {
    std::vector<std::uint8_t> labels(mesh.n_faces());
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        labels[f] = faceCentroid(mesh, f).x() < 0.0f ? 19 : 0;
    }
    labels[3] = kUnknownLabel;
    return labels;
}

}  // namespace

TEST_CASE("semantic PLY and OBJ load back with labels, colours and materials", "[semantic]") {
    const LabelSet labels = LabelSet::defaults();
    TriMesh mesh;
    addGrid(mesh, 1.0, 0.25, 0.0);
    const auto face_labels = halfLabels(mesh);
    const auto dir = scratchDir("semantic_export");

    writeSemanticPly(dir / "mesh.ply", mesh, face_labels, labels);
    std::vector<std::uint8_t> read_labels;
    const TriMesh back = readMeshPly(dir / "mesh.ply", &read_labels);
    REQUIRE(back.n_faces() == mesh.n_faces());
    REQUIRE(read_labels == face_labels);

    writeSemanticObj(dir / "mesh.obj", mesh, face_labels, labels);
    REQUIRE(std::filesystem::exists(dir / "mesh.mtl"));
    const ObjMesh obj = readObj(dir / "mesh.obj");
    REQUIRE(obj.triangles.size() == mesh.n_faces());
    REQUIRE(obj.materials.size() == labels.size() + 1);
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        const ObjMaterial& m = obj.materials.at(obj.triangles[f].material);
        REQUIRE(m.name == classMaterialName(face_labels[f], labels));
        const auto rgb = labels.color(face_labels[f]);
        REQUIRE(m.diffuse[0] == Approx(rgb[0] / 255.0f).margin(2e-3));
        REQUIRE(m.diffuse[2] == Approx(rgb[2] / 255.0f).margin(2e-3));
    }
    REQUIRE(classMaterialName(19, labels) == "class_19_lane_marking");
    REQUIRE(classMaterialName(kUnknownLabel, labels) == "unknown");
}

TEST_CASE("class meshes and statistics", "[semantic]") {
    const LabelSet labels = LabelSet::defaults();
    TriMesh mesh;
    addGrid(mesh, 1.0, 0.25, 0.0);
    const auto face_labels = halfLabels(mesh);
    const auto stats = classStatistics(mesh, face_labels);
    REQUIRE(stats.at(19).faces == 63);
    REQUIRE(stats.at(0).faces == 64);
    REQUIRE(stats.at(kUnknownLabel).faces == 1);
    REQUIRE(stats.at(0).area_m2 == Approx(2.0));
    REQUIRE(stats.at(19).area_m2 + stats.at(kUnknownLabel).area_m2 == Approx(2.0));

    const TriMesh lanes = extractClassMesh(mesh, face_labels, 19);
    REQUIRE(lanes.n_faces() == 63);
    for (const auto vh : lanes.vertices()) REQUIRE(lanes.point(vh)[0] <= 0.0f);
    REQUIRE(extractClassMesh(mesh, face_labels, 5).n_faces() == 0);
    REQUIRE(classMeshFileName(19, labels) == "class_19_lane_marking.ply");

    setFaceLabelProperty(mesh, face_labels);
    OpenMesh::FPropHandleT<std::uint8_t> prop;
    REQUIRE(mesh.get_property_handle(prop, kFaceLabelProperty));
    REQUIRE(mesh.property(prop, TriMesh::FaceHandle(3)) == kUnknownLabel);
    REQUIRE_THROWS_AS(setFaceLabelProperty(mesh, {1, 2}), InvalidInput);
}

TEST_CASE("the label grid holds the class of the nearest face", "[semantic]") {
    TriMesh mesh;
    addGrid(mesh, 1.0, 0.25, 0.0);
    std::vector<std::uint8_t> face_labels(mesh.n_faces());
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        face_labels[f] = faceCentroid(mesh, f).x() < 0.0f ? 19 : 0;
    }
    const auto transform = openvdb::math::Transform::createLinearTransform(0.1);
    const auto grid = labelGrid(mesh, face_labels, *transform, 2.0f);
    REQUIRE(grid->activeVoxelCount() > 0);
    auto acc = grid->getConstAccessor();
    auto at = [&](double x, double y, double z) {
        return acc.getValue(transform->worldToIndexNodeCentered(openvdb::Vec3d(x, y, z)));
    };
    REQUIRE(at(-0.5, 0.3, 0.1) == 19.0f);
    REQUIRE(at(0.5, -0.3, -0.1) == 0.0f);
    REQUIRE(at(0.5, 0.0, 3.0) == 255.0f);  // far from the mesh: background unknown
    REQUIRE_THROWS_AS(labelGrid(mesh, {1}, *transform, 2.0f), InvalidInput);
}
