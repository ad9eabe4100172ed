// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/Context.h"

#include "vdbmap/Error.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/map/VoxelMap.h"

namespace vdbmap {

Context::Context(std::filesystem::path output_dir, Report& report, bool quiet)
    : output_dir_(std::move(output_dir)), report_(report), quiet_(quiet) {}

Context::~Context() = default;

const Dataset& Context::dataset() const {
    if (!dataset_) throw Error("Context: the pipeline has no dataset section");
    return *dataset_;
}

VoxelMap& Context::map() {
    if (!map_) throw Error("Context: no stage has created a map (add integrate.atsdf first)");
    return *map_;
}

TriMesh& Context::mesh() {
    if (!mesh_) throw Error("Context: no stage has created a mesh (add mesh.marching_cubes)");
    return *mesh_;
}

}  // namespace vdbmap
