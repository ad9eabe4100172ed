// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vdbmap/mesh/TriMesh.h"
#include "vdbmap/render/Visibility.h"
#include "vdbmap/render/VisibilityKey.h"

namespace vdbmap {

class Dataset;
class VoxelMap;
class Report;
class ScanStream;
struct Tile;
class ContextBuilder;
class MovingReturns;

/// Everything stages share: the dataset (read-only), the map, the mesh, the report, the output
/// folder and the run flags. Stages share state only through this object.
///
/// Tiled runs (`tiling:` in the pipeline) give each mesh stage one Context per ground tile:
/// outputDir() is the tile's folder (tiles/<ix>_<iy>/), report() the tile's report, mesh() the
/// tile's mesh (core and halo faces, haloFaces()), views() the views assigned to the tile and
/// tile() its bounds. A stage written against views(), haloFaces() and outputDir() runs
/// unchanged in tiled and untiled runs; it writes only its core faces.
///
/// Streamed tiled runs finish tiles while the scans are integrated: a stage that integrates
/// the dataset's scans asks beginScanStream() which frames to read and calls scanIntegrated()
/// after each one. In a tile's context, the map is complete only within the tile's occluder
/// region (the tile grown by max(halo_m, occluder_margin_m)).
///
/// A stage reads the run's state and writes its outputs (setMesh, setOccluderMesh,
/// writeOutput, report()). What only the pipeline sets (the dataset, the map, the tile, the scan
/// stream) goes through ContextBuilder, which is not installed.
class Context {
public:
    Context(std::filesystem::path output_dir, Report& report, bool quiet = false);
    ~Context();

    /// The output folder (exists; a tile's folder in tiled runs). Stages write their files
    /// below it (docs/DATA.md layout).
    const std::filesystem::path& outputDir() const { return output_dir_; }
    /// Writes `content` to outputDir() / relative_path atomically (folders created). Throws
    /// InvalidInput for an absolute path or one with "..", IoError on write errors.
    void writeOutput(const std::filesystem::path& relative_path, std::string_view content) const;
    Report& report() { return report_; }
    /// True under --quiet: no progress bars, info logs off.
    bool quiet() const { return quiet_; }

    bool hasDataset() const { return dataset_ != nullptr; }
    /// Throws Error if the pipeline has no dataset section.
    const Dataset& dataset() const;

    bool hasMap() const { return map_ != nullptr; }
    /// Throws Error if no stage created a map.
    VoxelMap& map();
    const VoxelMap& map() const;
    std::shared_ptr<const VoxelMap> mapPtr() const { return map_; }

    bool hasMesh() const { return mesh_ != nullptr; }
    /// Throws Error if no stage created a mesh.
    TriMesh& mesh();
    const TriMesh& mesh() const;
    std::shared_ptr<const TriMesh> meshPtr() const { return mesh_; }
    void setMesh(std::shared_ptr<TriMesh> mesh) { mesh_ = std::move(mesh); }

    /// The mesh visibility tests should use as occluder: in a tiled run the tile's mesh grown by
    /// tiling.occluder_margin_m (geometry outside the tile still hides it), else mesh().
    const TriMesh& occluderMesh() const { return occluder_ ? *occluder_ : mesh(); }
    void setOccluderMesh(std::shared_ptr<const TriMesh> mesh) { occluder_ = std::move(mesh); }

    /// The returns integrate.atsdf removed as moving, per frame (docs/dynamic.md), or nullptr
    /// when its moving-object removal is off or no stage integrated scans. In a streamed tiled
    /// run it is complete for the frames of a tile's views when the tile's stages run.
    std::shared_ptr<const MovingReturns> movingReturns() const { return moving_; }

    /// Visibility a stage computed (meshVisibility, then removeScanOccluded) for a later stage
    /// of this context that asks for the same inputs: texture.mrf and semantic.mrf see the same
    /// faces from the same views. `key` is visibilityKey() of the inputs
    /// (vdbmap/render/VisibilityKey.h). It is kept until a stage asks for another, or until the
    /// end of the stage after the one that kept it; keeping another replaces it.
    void keepVisibility(std::string key, SharedVisibility visibility);
    /// The kept visibility, moved out and narrowed to `max_view_angle_deg` (narrowViewAngle),
    /// if its key is `key` and it was computed with at least that angle; otherwise std::nullopt,
    /// and the kept one is dropped (no later stage of this context can ask for it any more).
    std::optional<SharedVisibility> takeVisibility(const std::string& key,
                                                   double max_view_angle_deg);

    /// True in the per-tile contexts of a tiled run.
    bool hasTile() const { return tile_ != nullptr; }
    /// The tile (key, core and halo bounds in W, assigned views). Throws Error if untiled.
    const Tile& tile() const;

    /// A context for a stage's own work on another region (semantic.mrf labels the tile grown
    /// to its occluder margin): the same dataset, map, output folder and flags, `tile` as its
    /// tile, `report` as its report, no mesh yet (setMesh). The pipeline never sees it; this
    /// context is not changed.
    std::unique_ptr<Context> regionContext(std::shared_ptr<const Tile> tile, Report& report) const;

    /// The views of the dataset a mesh stage works with, filtered like datasetViews(): in a
    /// tiled run only those assigned to the tile, else all. Throws Error without a dataset.
    std::vector<View> views(bool need_images, bool need_semantics) const;
    /// One flag per face of mesh() (1 = halo face: take it into coupled decisions, do not
    /// write it); all 0 in untiled runs. Throws Error without a mesh.
    std::vector<std::uint8_t> haloFaces() const;

    /// For a stage that integrates the dataset's scans, before the first one: `update_reach_m`
    /// is how far beyond a point (metres) one scan can change the map. Returns the frames to
    /// integrate, ascending: every frame, or in a distributed run the frames whose scans can
    /// reach this process's tiles. Throws Error without a dataset.
    std::vector<std::size_t> beginScanStream(double update_reach_m);
    /// Call after integrating each frame beginScanStream() returned (the map must be set): in
    /// a streamed tiled run it finishes every tile no later scan or view can change (runs the
    /// tile stages, writes the tile, frees it). Throws what those stages throw.
    void scanIntegrated(std::size_t frame);
    /// The frames a stage reading per-point data (scans, LiDAR labels) should read: in a tile's
    /// context those whose scans can reach the tile (all frames if the run was not planned
    /// from the poses), else the frames of beginScanStream() (all frames before it).
    std::vector<std::size_t> scanFrames() const;
    /// This process's rank and the number of processes of a distributed run (vdbmap-mpi);
    /// 0 and 1 otherwise. A stage writing one run-wide file writes it only when processes()
    /// is 1, or leaves a part for process 0 to merge (dynamic_points.ply).
    int process() const;
    int processes() const;

private:
    friend class ContextBuilder;  ///< the pipeline's setters (src/pipeline/ContextBuilder.h)
    std::filesystem::path output_dir_;
    Report& report_;
    bool quiet_;
    std::shared_ptr<const Dataset> dataset_;
    std::shared_ptr<VoxelMap> map_;
    std::shared_ptr<TriMesh> mesh_;
    std::shared_ptr<const Tile> tile_;
    std::shared_ptr<const TriMesh> occluder_;
    std::shared_ptr<const MovingReturns> moving_;
    std::shared_ptr<ScanStream> stream_;
    struct KeptVisibility {
        std::string key;
        SharedVisibility visibility;
        bool kept_in_this_stage = true;
    };
    std::unique_ptr<KeptVisibility> kept_visibility_;
};

}  // namespace vdbmap
