// SPDX-License-Identifier: Apache-2.0
#include "pipeline/PipelineImpl.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/VdbIO.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"

namespace vdbmap::detail {

void writePipelineOutputs(Context& ctx, const OutputConfig& output, Report& report,
                          bool map_per_tile) {
    if (ctx.hasMap() && !map_per_tile) {
        const VoxelMap& map = ctx.map();
        report.set({"counts", "active_voxels"}, map.activeVoxelCount());
        report.set({"counts", "voxel_size_m"}, map.voxelSize());
        if (output.write_map) {
            const auto path = ctx.outputDir() / "map.vdb";
            writeMapVdb(path, map);
            report.set({"outputs", "map"}, path.string());
            logInfo("wrote " + path.string());
        }
    }
    if (ctx.hasMesh()) {
        const TriMesh& mesh = ctx.mesh();
        report.set({"counts", "vertices"}, mesh.n_vertices());
        report.set({"counts", "faces"}, mesh.n_faces());
        if (output.write_mesh) {
            const auto path = ctx.outputDir() / "mesh.ply";
            writeMeshPly(path, mesh);
            report.set({"outputs", "mesh"}, path.string());
            logInfo("wrote " + path.string());
        }
    }
}

}  // namespace vdbmap::detail
