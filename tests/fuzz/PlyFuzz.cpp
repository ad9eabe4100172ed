// SPDX-License-Identifier: Apache-2.0
// PLY, ascii and binary (both endians): every input goes to the point reader and the mesh
// reader (with face labels and the count of faces OpenMesh refuses).
#include "FuzzSupport.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/io/PointCloudIO.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    const auto path = fuzz::writeInput("cloud.ply", fuzz::asText(data, size));
    fuzz::refusesOnlyWithTypedErrors([&] { readPlyPoints(path); });
    fuzz::refusesOnlyWithTypedErrors([&] {
        std::vector<std::uint8_t> labels;
        PlyReadStats stats;
        const TriMesh mesh = readMeshPly(path, &labels, &stats);
        if (stats.triangles - stats.rejected_triangles != mesh.n_faces()) std::abort();
        if (!labels.empty() && labels.size() != mesh.n_faces()) std::abort();
    });
    return 0;
}
