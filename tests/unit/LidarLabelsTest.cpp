// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <functional>

#include "vdbmap/Error.h"
#include "vdbmap/io/LidarLabels.h"

using namespace vdbmap;

namespace {

std::filesystem::path scratch(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / "vdbmap_lidar_labels_test";
    std::filesystem::create_directories(dir);
    return dir / name;
}

void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const IoError& e) {
        return e.what();
    }
    return "(no IoError)";
}

}  // namespace

TEST_CASE("a .label file: lower 16 bits class, upper 16 instance, little endian", "[io][labels]") {
    // Entry 0: class 40 (road), instance 7; entry 1: class 252 (moving car), instance 65535.
    const std::string bytes("\x28\x00\x07\x00\xfc\x00\xff\xff", 8);
    const auto path = scratch("good.label");
    writeBytes(path, bytes);
    const LidarLabels labels = readLidarLabels(path);
    REQUIRE(labels.size() == 2);
    CHECK(labels.raw[0] == 0x00070028u);
    CHECK(LidarLabels::classOf(labels.raw[0]) == 40);
    CHECK(LidarLabels::instanceOf(labels.raw[0]) == 7);
    CHECK(LidarLabels::classOf(labels.raw[1]) == 252);
    CHECK(LidarLabels::instanceOf(labels.raw[1]) == 65535);

    // Round trip through the writer; an empty file is an empty scan's labels.
    writeLidarLabels(scratch("copy.label"), labels);
    CHECK(readLidarLabels(scratch("copy.label")).raw == labels.raw);
    writeBytes(scratch("empty.label"), "");
    CHECK(readLidarLabels(scratch("empty.label")).size() == 0);
    CHECK(parseLidarLabels(nullptr, 0, "none").size() == 0);
}

TEST_CASE("bad .label files name the file and the problem", "[io][labels]") {
    const auto path = scratch("truncated.label");
    writeBytes(path, std::string("\x28\x00\x07\x00\x30", 5));
    const std::string truncated = messageOf([&] { readLidarLabels(path); });
    CHECK_THAT(truncated, Catch::Contains(path.string()));
    CHECK_THAT(truncated, Catch::Contains("5 bytes"));
    const std::string missing = messageOf([&] { readLidarLabels(scratch("missing.label")); });
    CHECK_THAT(missing, Catch::Contains("missing.label"));

    // One label per point: both files and both counts in the message.
    CHECK_NOTHROW(checkLabelCount(3, "a.label", 3, "a.bin"));
    const std::string count = messageOf([] { checkLabelCount(1000, "x/000004.label", 1001, "x/000004.bin"); });
    CHECK_THAT(count, Catch::Contains("x/000004.label") && Catch::Contains("x/000004.bin") &&
                          Catch::Contains("1000 labels") && Catch::Contains("1001 points"));
}

TEST_CASE("label maps: parse, map, and reject unknown ids", "[io][labels]") {
    const LabelMap map = LabelMap::parse("# comment\n40 0  # road\n\n48 1\n0 255 # unlabeled\n",
                                         "my.map");
    CHECK(map.size() == 3);
    CHECK(map.contains(40));
    CHECK(map(40) == 0);
    CHECK(map(0) == 255);
    CHECK_FALSE(map.contains(10));

    LidarLabels labels;
    labels.raw = {40u | (3u << 16), 48u, 0u};
    CHECK(mapLidarLabels(labels, "s.label", map) == std::vector<std::uint8_t>{0, 1, 255});

    // An id the map does not know: the label file, the map file, the id and its count.
    labels.raw = {40u, 10u, 10u | (5u << 16), 11u};
    const std::string unknown = messageOf([&] { mapLidarLabels(labels, "seq/000002.label", map); });
    CHECK_THAT(unknown, Catch::Contains("seq/000002.label") && Catch::Contains("my.map") &&
                            Catch::Contains("class id 10") && Catch::Contains("2 of 4 points") &&
                            Catch::Contains("2 unknown ids"));

    // Malformed lines name the file, the line and its text.
    CHECK_THAT(messageOf([] { LabelMap::parse("40 0\n48\n", "m"); }),
               Catch::Contains("m:2: '48'"));
    CHECK_THAT(messageOf([] { LabelMap::parse("40 256\n", "m"); }), Catch::Contains("0..255"));
    CHECK_THAT(messageOf([] { LabelMap::parse("70000 1\n", "m"); }),
               Catch::Contains("0..65535"));
    CHECK_THAT(messageOf([] { LabelMap::parse("-1 1\n", "m"); }), Catch::Contains("m:1"));
    CHECK_THAT(messageOf([] { LabelMap::parse("40 0\n40 1\n", "m"); }),
               Catch::Contains("mapped twice"));
    CHECK_THAT(messageOf([] { LabelMap::parse("40 0 7\n", "m"); }), Catch::Contains("m:1"));

    // Identity: our own ids need no map; larger ids are unknown.
    const LabelMap identity = LabelMap::identity();
    CHECK(identity(19) == 19);
    CHECK_FALSE(identity.contains(256));
}

TEST_CASE("the shipped SemanticKITTI map equals the built-in one", "[io][labels]") {
    const LabelMap file = LabelMap::fromFile(std::filesystem::path(VDBMAP_SOURCE_DIR) / "config" /
                                             "label_maps" / "semantickitti.txt");
    const LabelMap builtin = LabelMap::semanticKitti();
    CHECK(file == builtin);
    CHECK(builtin.size() == 34);
    CHECK(builtin(40) == 0);   // road
    CHECK(builtin(48) == 1);   // sidewalk
    CHECK(builtin(50) == 2);   // building
    CHECK(builtin(60) == 19);  // lane marking
    CHECK(builtin(99) == 20);  // other object
    CHECK(builtin(0) == 255);  // unlabeled -> void
}
