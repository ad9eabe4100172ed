// SPDX-License-Identifier: Apache-2.0
// readMeshPly counts the faces OpenMesh refuses (a third face on an edge, repeated corners),
// and `vdbmap eval` refuses a ground truth that lost faces on reading.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "support/CliRun.h"
#include "vdbmap/io/MeshIO.h"

using namespace vdbmap;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

fs::path workDir() {
    static const fs::path dir = [] {
        const fs::path d = test::freshProcessDir("vdbmap_plydrop");
        return d;
    }();
    static const test::RemoveAtExit cleanup{dir};
    return dir;
}

/// Five vertices; faces 0 and 1 share edge 0-1, face 2 is a third face on that edge, face 3
/// repeats a corner, face 4 is a quad (two triangles, both fine), all labelled 10 + index.
fs::path writeFaultyPly(const fs::path& path) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 5\n"
                           "property list uchar int vertex_indices\nproperty uchar label\n"
                           "end_header\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n5 5 0\n"
                           "3 0 1 2 10\n3 1 0 3 11\n3 0 1 4 12\n3 2 2 5 13\n4 2 4 5 3 14\n";
    return path;
}

}  // namespace

TEST_CASE("PLY mesh: the faces OpenMesh refuses are counted", "[io][ply]") {
    const fs::path path = writeFaultyPly(workDir() / "faulty.ply");
    std::vector<std::uint8_t> labels;
    PlyReadStats stats;
    const TriMesh mesh = readMeshPly(path, &labels, &stats);
    CHECK(stats.file_faces == 5);
    CHECK(stats.triangles == 6);           // 4 triangles + the quad's two
    CHECK(stats.rejected_triangles == 2);  // the third face on edge 0-1, the repeated corner
    CHECK(mesh.n_faces() == 4);
    // Labels stay aligned with the faces that exist.
    CHECK(labels == std::vector<std::uint8_t>{10, 11, 14, 14});
}

TEST_CASE("vdbmap eval refuses a ground truth that lost faces", "[cli][eval][hardening]") {
    const fs::path seq = workDir() / "seq";
    writeFaultyPly(seq / "gt" / "mesh.ply");
    fs::create_directories(workDir() / "run");
    test::Child child(test::kVdbmapExe, {"eval", "--gt", (seq / "gt").string(), "--run",
                                         (workDir() / "run").string()});
    CHECK(child.exitCode() == 1);
    CHECK_THAT(child.log(), Contains("mesh.ply") && Contains("lost 2 of 6 triangles") &&
                                Contains("refusing"));
}
