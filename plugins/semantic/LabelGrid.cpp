// SPDX-License-Identifier: Apache-2.0
#include "LabelGrid.h"

#include <openvdb/tools/MeshToVolume.h>

#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/map/Layers.h"

namespace vdbmap::semantic {

openvdb::FloatGrid::Ptr labelGrid(const TriMesh& mesh, const std::vector<std::uint8_t>& face_labels,
                                  const openvdb::math::Transform& transform, float band_vox) {
    if (face_labels.size() != mesh.n_faces()) {
        throw InvalidInput("labelGrid: " + std::to_string(face_labels.size()) +
                           " face labels for a mesh of " + std::to_string(mesh.n_faces()) +
                           " faces");
    }
    if (!(band_vox >= 1.0f)) {
        throw InvalidInput("labelGrid: band_vox must be >= 1, got " + std::to_string(band_vox));
    }
    // The grid outlives the plugin's stage (the pipeline writes map.vdb later), so it is
    // built by OpenVDB's registered factory and its virtual functions live in libopenvdb.
    // Inside a dlopen'ed hidden-visibility module, Tree::treeType() (std::call_once on a
    // module-local static) crashes, so this file never calls type() / gridType() itself:
    // the type name is spelled out and checked through the library's virtual type().
    const std::string float_grid_type = "Tree_float_5_4_3";
    openvdb::FloatGrid::Ptr grid;
    if (openvdb::GridBase::isRegistered(float_grid_type)) {
        openvdb::GridBase::Ptr base = openvdb::GridBase::createGrid(float_grid_type);
        if (base && base->type() == float_grid_type) {
            grid = openvdb::StaticPtrCast<openvdb::FloatGrid>(base);
        }
    }
    if (!grid) grid = openvdb::FloatGrid::create();
    grid->tree().root().setBackground(static_cast<float>(kUnknownLabel), true);
    grid->setTransform(transform.copy());
    grid->setName(grids::kLabel);
    grid->setGridClass(openvdb::GRID_UNKNOWN);
    if (mesh.n_faces() == 0) return grid;

    std::vector<openvdb::Vec3s> points_index;
    points_index.reserve(mesh.n_vertices());
    for (const auto vh : mesh.vertices()) {
        const openvdb::Vec3d p = transform.worldToIndex(
            openvdb::Vec3d(mesh.point(vh)[0], mesh.point(vh)[1], mesh.point(vh)[2]));
        points_index.emplace_back(p);
    }
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(mesh.n_faces());
    for (const auto fh : mesh.faces()) {
        openvdb::Vec3I t;
        int k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            if (k < 3) t[k++] = static_cast<openvdb::Index32>(vh.idx());
        }
        triangles.push_back(t);
    }
    openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(
        points_index, triangles);
    openvdb::Int32Grid index_grid(0);
    // Unsigned distance: the street mesh is open, so inside / outside has no meaning here.
    openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        adapter, transform, band_vox, band_vox, openvdb::tools::UNSIGNED_DISTANCE_FIELD,
        &index_grid);
    auto accessor = grid->getAccessor();
    for (auto it = index_grid.cbeginValueOn(); it; ++it) {
        const auto face = static_cast<std::size_t>(*it);
        if (face >= face_labels.size()) continue;
        const std::uint8_t id = face_labels[face];
        if (id == kUnknownLabel) continue;
        accessor.setValue(it.getCoord(), static_cast<float>(id));
    }
    return grid;
}

}  // namespace vdbmap::semantic
