// SPDX-License-Identifier: Apache-2.0
// texture.mrf on a surround-rig street: every camera of the rig is a candidate view.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "vdbmap/core/Log.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "support/SimRigFixture.h"

namespace fs = std::filesystem;

TEST_CASE("texture.mrf textures from every camera of a surround rig", "[texture][pipeline][rig]") {
    vdbmap::setLogLevel(vdbmap::LogLevel::Warn);
    const fs::path root = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "texture_rig";
    fs::remove_all(root);
    std::string yaml = vdbmap::test::rigDatasetYaml(root);
    const std::string plugin =
        (fs::path(VDBMAP_PLUGIN_BUILD_DIR) / "vdbmap_plugin_texture.so").string();
    yaml += "plugins: [\"" + plugin +
            "\"]\n"
            "stages:\n"
            "  - stage: integrate.atsdf\n"
            "    voxel_size_m: 0.2\n"
            "  - stage: mesh.marching_cubes\n"
            "  - stage: texture.mrf\n"
            "    vignetting: true\n"
            "    vignetting_params: [0.3, 0.1, 0.05]\n";
    auto untextured = [&](const std::vector<std::string>& overrides, const std::string& name,
                          vdbmap::Report& report) {
        auto pipeline = vdbmap::Pipeline::fromString(yaml, "texture_rig_test", root, overrides);
        pipeline->run(root / name, report, true);
        REQUIRE(fs::exists(root / name / "textured" / "mesh.obj"));
        return std::stoul(report.getJson({"stages", "texture.mrf", "faces_untextured"}));
    };
    vdbmap::Report rig_report, front_report;
    const std::size_t rig = untextured({}, "rig", rig_report);
    const std::size_t front = untextured(
        {"dataset.cameras=[{name: front, image_dir: image_front, calib_file: calib_front.txt}]"},
        "front", front_report);
    CHECK(rig_report.getJson({"stages", "texture.mrf", "views"}) == "16");
    CHECK(front_report.getJson({"stages", "texture.mrf", "views"}) == "4");
    // The simulator's vignetting, one model per camera of the rig.
    CHECK(rig_report.getJson({"stages", "texture.mrf", "vignetting_abc", "camera_3"}) ==
          "[0.3,0.1,0.05]");
    CHECK(front_report.getJson({"stages", "texture.mrf", "vignetting_abc", "camera_1"}) == "null");
    const std::size_t faces = std::stoul(rig_report.getJson({"stages", "texture.mrf", "faces"}));
    // The forward camera misses what is behind and beside the car; the rig sees nearly all.
    CHECK(front > faces / 4);
    CHECK(rig < front / 3);
}
