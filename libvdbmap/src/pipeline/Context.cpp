// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/pipeline/Context.h"

#include <algorithm>
#include <numeric>

#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/TileFaces.h"
#include "vdbmap/pipeline/Tiling.h"
#include "pipeline/ContextBuilder.h"
#include "pipeline/ScanStream.h"

namespace vdbmap {

Context::Context(std::filesystem::path output_dir, Report& report, bool quiet)
    : output_dir_(std::move(output_dir)), report_(report), quiet_(quiet) {}

Context::~Context() = default;

void Context::writeOutput(const std::filesystem::path& relative_path,
                          std::string_view content) const {
    const bool up = std::any_of(relative_path.begin(), relative_path.end(),
                                [](const std::filesystem::path& part) { return part == ".."; });
    if (relative_path.empty() || relative_path.is_absolute() || up) {
        throw InvalidInput("Context::writeOutput: '" + relative_path.string() +
                           "' is not a path inside the output folder");
    }
    const std::filesystem::path path = output_dir_ / relative_path;
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) throw IoError(path.parent_path().string() + ": cannot create folder: " + ec.message());
    writeFileAtomically(path, content);
}

const Dataset& Context::dataset() const {
    if (!dataset_) throw Error("Context: the pipeline has no dataset section");
    return *dataset_;
}

VoxelMap& Context::map() {
    if (!map_) throw Error("Context: no stage has created a map (add integrate.atsdf first)");
    return *map_;
}

const VoxelMap& Context::map() const { return const_cast<Context*>(this)->map(); }

TriMesh& Context::mesh() {
    if (!mesh_) throw Error("Context: no stage has created a mesh (add mesh.marching_cubes)");
    return *mesh_;
}

const TriMesh& Context::mesh() const { return const_cast<Context*>(this)->mesh(); }

const Tile& Context::tile() const {
    if (!tile_) throw Error("Context: this run is not tiled (no `tiling:` section)");
    return *tile_;
}

std::unique_ptr<Context> Context::regionContext(std::shared_ptr<const Tile> tile,
                                                Report& report) const {
    return ContextBuilder::tileContext(*this, output_dir_, report, std::move(tile));
}

void Context::keepVisibility(std::string key, SharedVisibility visibility) {
    kept_visibility_ = std::make_unique<KeptVisibility>(
        KeptVisibility{std::move(key), std::move(visibility), true});
}

std::optional<SharedVisibility> Context::takeVisibility(const std::string& key,
                                                        double max_view_angle_deg) {
    if (!kept_visibility_) return std::nullopt;
    std::unique_ptr<KeptVisibility> kept = std::move(kept_visibility_);
    if (kept->key != key || kept->visibility.max_view_angle_deg < max_view_angle_deg) {
        return std::nullopt;
    }
    narrowViewAngle(kept->visibility, max_view_angle_deg);
    return std::optional<SharedVisibility>(std::move(kept->visibility));
}

std::vector<View> Context::views(bool need_images, bool need_semantics) const {
    std::vector<View> views = datasetViews(dataset(), need_images, need_semantics);
    if (!tile_) return views;
    // Both lists are ordered by (frame, camera).
    const auto& assigned = tile_->views;
    views.erase(std::remove_if(views.begin(), views.end(),
                               [&](const View& v) {
                                   return !std::binary_search(
                                       assigned.begin(), assigned.end(),
                                       std::make_pair(v.frame, v.camera));
                               }),
                views.end());
    return views;
}

std::vector<std::uint8_t> Context::haloFaces() const { return haloFaceMask(mesh()); }

std::vector<std::size_t> Context::beginScanStream(double update_reach_m) {
    if (stream_) return stream_->begin(dataset(), update_reach_m);
    std::vector<std::size_t> all(dataset().numFrames());
    std::iota(all.begin(), all.end(), std::size_t(0));
    return all;
}

int Context::process() const { return stream_ ? stream_->process() : 0; }

int Context::processes() const { return stream_ ? stream_->processes() : 1; }

void Context::scanIntegrated(std::size_t frame) {
    if (stream_) stream_->frameIntegrated(frame);
}

std::vector<std::size_t> Context::scanFrames() const {
    if (tile_ && !tile_->scan_frames.empty()) return tile_->scan_frames;
    if (!tile_ && stream_ && stream_->begun()) return stream_->frames();
    std::vector<std::size_t> all(dataset().numFrames());
    std::iota(all.begin(), all.end(), std::size_t(0));
    return all;
}

}  // namespace vdbmap
