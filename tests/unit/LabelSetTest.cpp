// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/LabelSet.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

TEST_CASE("Default label set is docs/DATA.md's table", "[io][labels]") {
    const LabelSet labels = LabelSet::defaults();
    REQUIRE(labels.size() == 21);
    CHECK(labels.name(0) == "road");
    CHECK(labels.color(0) == std::array<std::uint8_t, 3>{128, 64, 128});
    CHECK(labels.name(13) == "car");
    CHECK(labels.color(19) == std::array<std::uint8_t, 3>{255, 255, 255});
    CHECK(labels.color(20) == std::array<std::uint8_t, 3>{255, 128, 0});
    CHECK(labels.indexOf(255) == -1);
    CHECK(labels.indexOf(21) == -1);
    CHECK(labels.color(255) == std::array<std::uint8_t, 3>{0, 0, 0});
    CHECK(labels.indexOf(7) == 7);
}

TEST_CASE("config/labels_default.txt equals the built-in defaults", "[io][labels]") {
    const LabelSet file = LabelSet::fromFile(std::filesystem::path(VDBMAP_SOURCE_DIR) / "config" /
                                             "labels_default.txt");
    const LabelSet defaults = LabelSet::defaults();
    REQUIRE(file.size() == defaults.size());
    for (std::size_t i = 0; i < file.size(); ++i) {
        CHECK(file.classes()[i].id == defaults.classes()[i].id);
        CHECK(file.classes()[i].name == defaults.classes()[i].name);
        CHECK(file.classes()[i].rgb == defaults.classes()[i].rgb);
    }
}

TEST_CASE("Label files: custom sets and errors naming file and line", "[io][labels]") {
    test::TempDir dir;
    test::writeText(dir / "mine.txt",
                    "# my classes\n\n3, tree trunk, 10 20 30  # brown-ish\n"
                    "40, cone, 255 128 0\n255, void, 0 0 0\n");
    const LabelSet mine = LabelSet::fromFile(dir / "mine.txt");
    CHECK(mine.size() == 2);
    CHECK(mine.name(3) == "tree trunk");
    CHECK(mine.indexOf(40) == 1);
    CHECK(mine.color(40) == std::array<std::uint8_t, 3>{255, 128, 0});
    CHECK(mine.indexOf(0) == -1);

    test::writeText(dir / "a.txt", "0, road, 1 2 3\n1 sidewalk 4 5 6\n");
    CHECK_THAT(test::ioErrorMessage([&] { LabelSet::fromFile(dir / "a.txt"); }),
               Contains("a.txt:2"));
    test::writeText(dir / "b.txt", "0, road, 1 2 300\n");
    CHECK_THAT(test::ioErrorMessage([&] { LabelSet::fromFile(dir / "b.txt"); }),
               Contains("b.txt:1") && Contains("0..255"));
    test::writeText(dir / "c.txt", "0, road, 1 2 3\n0, again, 1 2 3\n");
    CHECK_THAT(test::ioErrorMessage([&] { LabelSet::fromFile(dir / "c.txt"); }),
               Contains("c.txt:2") && Contains("duplicate"));
    test::writeText(dir / "d.txt", "256, big, 1 2 3\n");
    CHECK_THAT(test::ioErrorMessage([&] { LabelSet::fromFile(dir / "d.txt"); }),
               Contains("d.txt:1"));
}
