// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <memory>
#include <utility>

#include "vdbmap/pipeline/Context.h"

namespace vdbmap {

class Dataset;
class ScanStream;
class VoxelMap;
struct Tile;

/// The pipeline's side of Context: what only the pipeline (and the built-in stage that creates
/// the map) sets. Not installed: plugins see Context's read access and its outputs (setMesh,
/// setOccluderMesh, writeOutput, report()), never these.
class ContextBuilder {
public:
    /// The dataset of the run (the pipeline, once, before the first stage).
    static void setDataset(Context& ctx, std::shared_ptr<const Dataset> dataset) {
        ctx.dataset_ = std::move(dataset);
    }
    /// The map (integrate.atsdf, before its first scan: streamed tiles read it).
    static void setMap(Context& ctx, std::shared_ptr<VoxelMap> map) { ctx.map_ = std::move(map); }
    /// The moving returns (integrate.atsdf, before its first scan, with its removal on).
    static void setMovingReturns(Context& ctx, std::shared_ptr<const MovingReturns> moving) {
        ctx.moving_ = std::move(moving);
    }
    /// The tile of a per-tile context (the pipeline; tests that build one by hand).
    static void setTile(Context& ctx, std::shared_ptr<const Tile> tile) { ctx.tile_ = std::move(tile); }
    /// The pipeline's side of streaming (tiled runs); nullptr ends it.
    static void setScanStream(Context& ctx, std::shared_ptr<ScanStream> stream) {
        ctx.stream_ = std::move(stream);
    }
    /// After each stage of `ctx` (the pipeline): the visibility a stage kept lives until the end
    /// of the next stage (Context::keepVisibility).
    static void stageEnded(Context& ctx) {
        if (!ctx.kept_visibility_) return;
        if (ctx.kept_visibility_->kept_in_this_stage) {
            ctx.kept_visibility_->kept_in_this_stage = false;
        } else {
            ctx.kept_visibility_.reset();
        }
    }
    /// The pipeline's side of streaming, or nullptr (untiled runs).
    static const ScanStream* scanStream(const Context& ctx) { return ctx.stream_.get(); }
    /// A context for one tile of a tiled run: the same dataset, map, moving returns and flags, the tile's
    /// folder and report, no mesh yet.
    static std::unique_ptr<Context> tileContext(const Context& ctx, std::filesystem::path tile_dir,
                                                Report& tile_report, std::shared_ptr<const Tile> tile) {
        auto out = std::make_unique<Context>(std::move(tile_dir), tile_report, ctx.quiet_);
        out->dataset_ = ctx.dataset_;
        out->map_ = ctx.map_;
        out->moving_ = ctx.moving_;
        out->tile_ = std::move(tile);
        return out;
    }
};

}  // namespace vdbmap
