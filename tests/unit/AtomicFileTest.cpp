// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <fstream>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/MeshIO.h"

using namespace vdbmap;

TEST_CASE("AtomicFile: commit renames the temporary over the final file", "[io][atomic]") {
    test::TempDir dir;
    const auto final_path = dir / "out" / "deep" / "report.json";
    {
        AtomicFile file(final_path);
        CHECK(file.tempPath().parent_path() == final_path.parent_path());
        CHECK(file.tempPath().extension() == ".json");
        std::ofstream(file.tempPath()) << "new";
        CHECK_FALSE(std::filesystem::exists(final_path));
        file.commit();
    }
    CHECK(test::readBytes(final_path) == "new");
    CHECK(test::countEntries(final_path.parent_path()) == 1);
}

TEST_CASE("AtomicFile: an exception leaves no temporary and the old file untouched",
          "[io][atomic]") {
    test::TempDir dir;
    const auto final_path = dir / "mesh.ply";
    test::writeText(final_path, "old content");
    std::filesystem::path temp;
    try {
        AtomicFile file(final_path);
        temp = file.tempPath();
        std::ofstream(file.tempPath()) << "half written";
        throw std::runtime_error("stage failed");
    } catch (const std::runtime_error&) {
    }
    CHECK_FALSE(temp.empty());
    CHECK_FALSE(std::filesystem::exists(temp));
    CHECK(test::readBytes(final_path) == "old content");
    CHECK(test::countEntries(dir.path()) == 1);

    // A writer that fails half-way (bad face list) leaves the old file too.
    TriMesh mesh;
    mesh.add_vertex(TriMesh::Point(0, 0, 0));
    const std::vector<std::uint8_t> labels(5, 1);
    PlyWriteOptions options;
    options.face_labels = &labels;
    CHECK_THROWS_AS(writeMeshPly(final_path, mesh, options), InvalidInput);
    CHECK(test::readBytes(final_path) == "old content");
    CHECK(test::countEntries(dir.path()) == 1);
}

TEST_CASE("AtomicFile errors: nothing written, unwritable folder", "[io][atomic]") {
    test::TempDir dir;
    AtomicFile file(dir / "x.txt");
    CHECK_THAT(test::ioErrorMessage([&] { file.commit(); }), Catch::Contains("x.txt"));
    test::writeText(dir / "plain", "a file, not a folder");
    CHECK_THAT(test::ioErrorMessage([&] { AtomicFile inside(dir / "plain" / "y.txt"); }),
               Catch::Contains("plain"));
    CHECK_THROWS_AS(AtomicFile(""), InvalidInput);
    writeFileAtomically(dir / "z.txt", "zz");
    CHECK(test::readBytes(dir / "z.txt") == "zz");
}
