// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <memory>

#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

class Dataset;
class VoxelMap;
class Report;

/// Everything stages share: the dataset (read-only), the map, the mesh, the report, the output
/// folder and the run flags. Stages share state only through this object.
class Context {
public:
    Context(std::filesystem::path output_dir, Report& report, bool quiet = false);
    ~Context();

    /// The output folder (exists). Stages write their files below it (DATA.md layout).
    const std::filesystem::path& outputDir() const { return output_dir_; }
    Report& report() { return report_; }
    /// True under --quiet: no progress bars, info logs off.
    bool quiet() const { return quiet_; }

    bool hasDataset() const { return dataset_ != nullptr; }
    /// Throws Error if the pipeline has no dataset section.
    const Dataset& dataset() const;
    void setDataset(std::shared_ptr<const Dataset> dataset) { dataset_ = std::move(dataset); }

    bool hasMap() const { return map_ != nullptr; }
    /// Throws Error if no stage created a map.
    VoxelMap& map();
    std::shared_ptr<VoxelMap> mapPtr() const { return map_; }
    void setMap(std::shared_ptr<VoxelMap> map) { map_ = std::move(map); }

    bool hasMesh() const { return mesh_ != nullptr; }
    /// Throws Error if no stage created a mesh.
    TriMesh& mesh();
    std::shared_ptr<TriMesh> meshPtr() const { return mesh_; }
    void setMesh(std::shared_ptr<TriMesh> mesh) { mesh_ = std::move(mesh); }

private:
    std::filesystem::path output_dir_;
    Report& report_;
    bool quiet_;
    std::shared_ptr<const Dataset> dataset_;
    std::shared_ptr<VoxelMap> map_;
    std::shared_ptr<TriMesh> mesh_;
};

}  // namespace vdbmap
