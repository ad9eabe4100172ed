// SPDX-License-Identifier: Apache-2.0
// The tiled pipeline end to end (issue 13): a simulated street crossing several tiles, run
// tiled and untiled with the texture and semantic plugins; the tiles' meshes are the untiled
// mesh, their labels agree, tiles.json indexes existing files, failures leave no index.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "support/OutputCompare.h"
#include "support/PluginPath.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/ViewFrustum.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;
using namespace vdbmap;
using vdbmap::test::filesBelow;
using vdbmap::test::readText;
using vdbmap::test::vdbVoxels;

namespace {

using Point = std::array<float, 3>;
using Face = std::array<Point, 3>;

/// Faces as rotated corner triples (orientation kept), each with its label (or 0).
std::map<Face, int> labelledFaces(const TriMesh& mesh, const std::vector<std::uint8_t>* labels) {
    std::map<Face, int> out;
    for (const auto fh : mesh.faces()) {
        Face f{};
        int k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            const auto p = mesh.point(vh);
            f[static_cast<std::size_t>(k++)] = {p[0], p[1], p[2]};
        }
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        const int label = labels ? (*labels)[static_cast<std::size_t>(fh.idx())] : 0;
        REQUIRE(out.emplace(f, label).second);  // no face twice
    }
    return out;
}

std::string plugin(const char* name) { return test::builtPluginPath(name); }

std::string streetYaml(const std::string& extra_semantic, const std::string& tiling,
                       const std::string& dataset_extra = "", bool texture = true) {
    return "dataset: {format: kitti, path: seq, min_range_m: 1.0" + dataset_extra + "}\n"
           "plugins: [\"" + plugin("texture") + "\", \"" + plugin("semantic") + "\"]\n"
           "stages:\n"
           "  - stage: integrate.atsdf\n"
           "    voxel_size_m: 0.2\n"
           "  - stage: mesh.marching_cubes\n" +
           std::string(texture ? "  - stage: texture.mrf\n"
                                 "    max_view_angle_deg: 85\n"
                               : "") +
           "  - stage: semantic.mrf\n"
           "    max_view_angle_deg: 88\n" + extra_semantic + tiling;
}

/// A simulated street in its own folder per test case (ctest runs test cases in parallel).
fs::path streetRoot(const std::string& test, std::size_t frames = 6, double size_m = 36.0) {
    static std::map<std::string, fs::path> roots;
    if (roots.count(test)) return roots[test];
    const fs::path root = [&] {
        setLogLevel(LogLevel::Warn);
        const fs::path r = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / ("tiled_pipeline_" + test);
        fs::remove_all(r);
        SimOptions sim;
        sim.frames = frames;
        sim.size_m = size_m;
        sim.gt_views = 0;
        sim.quiet = true;
        writeSimSequence(sim, r / "seq");
        return r;
    }();
    roots[test] = root;
    return root;
}

}  // namespace

TEST_CASE("A tiled run gives the untiled mesh and labels, tile by tile", "[tiles][pipeline][heavy]") {
    const fs::path root = streetRoot("agree");
    // Small tiles (6.4 m, 32 voxels) so that most faces lie near a border. With a halo as wide
    // as the street, each tile's MRF sees everything and only the decomposition differs; with
    // a 2 m halo the Potts MRF is cut 2 m past the border (alpha-expansion reaches another
    // local optimum on the smaller graph), and agreement is lower. The wide halo gives every
    // tile the whole street, so that row uses 12.8 m tiles (still crossing tile corners) and
    // leaves the texture stage out (it would texture the street once per tile; the labels and
    // the mesh do not depend on it). The narrow row's occluders reach 3 m past the halo.
    const auto [halo_m, min_agreement] = GENERATE(table<double, double>({{2.0, 0.9}, {60.0, 0.995}}));
    const bool wide = halo_m > 10.0;
    const double tile_size_m = wide ? 12.8 : 6.4;
    INFO("halo " << halo_m << " m");
    const std::string tiling = "tiling: {tile_size_m: " + std::to_string(tile_size_m) +
                               ", halo_m: " + std::to_string(halo_m) +
                               (wide ? "" : ", occluder_margin_m: 3") +
                               ", max_view_distance_m: 200}\n";
    Report untiled_report, tiled_report;
    if (!fs::exists(root / "untiled" / "report.json")) {
        Pipeline::fromString(streetYaml("", ""), "untiled", root)
            ->run(root / "untiled", untiled_report, true);
    }
    fs::remove_all(root / "tiled");
    Pipeline::fromString(streetYaml("", tiling, "", /*texture=*/!wide), "tiled", root)
        ->run(root / "tiled", tiled_report, true);

    const fs::path out = root / "tiled";
    REQUIRE(fs::exists(out / "tiles.json"));
    CHECK(fs::exists(out / "map.vdb"));
    CHECK_FALSE(fs::exists(out / "mesh.ply"));  // no merge
    std::ifstream in(out / "tiles.json");
    const nlohmann::json index = nlohmann::json::parse(in);
    CHECK(index["up_axis"] == "y");  // KITTI W: camera 0, y points down
    CHECK(index["tile_size_m"].get<double>() == Approx(tile_size_m));
    const auto& tiles = index["tiles"];
    REQUIRE(tiles.size() >= 4);

    std::vector<std::uint8_t> labels;
    const auto untiled_mesh = readMeshPly(root / "untiled" / "mesh.ply");
    const auto untiled_semantic = readMeshPly(root / "untiled" / "semantic" / "mesh.ply", &labels);
    const auto reference = labelledFaces(untiled_mesh, nullptr);
    const auto reference_labels = labelledFaces(untiled_semantic, &labels);
    std::map<Face, int> union_mesh, union_labels;
    std::size_t face_sum = 0;
    for (const auto& tile : tiles) {
        const std::string name = tile["name"];
        INFO("tile " << name);
        for (const auto& file : tile["files"]) CHECK(fs::exists(out / file.get<std::string>()));
        const fs::path dir = out / "tiles" / name;
        REQUIRE(fs::exists(dir / "mesh.ply"));
        const auto mesh = readMeshPly(dir / "mesh.ply");
        CHECK(mesh.n_faces() == tile["counts"]["faces"].get<std::size_t>());
        face_sum += mesh.n_faces();
        for (const auto& [face, label] : labelledFaces(mesh, nullptr)) {
            CHECK(union_mesh.emplace(face, label).second);  // owned by one tile only
        }
        if (fs::exists(dir / "semantic" / "mesh.ply")) {
            std::vector<std::uint8_t> tile_labels;
            const auto sem = readMeshPly(dir / "semantic" / "mesh.ply", &tile_labels);
            CHECK(sem.n_faces() == mesh.n_faces());
            const auto faces = labelledFaces(sem, &tile_labels);
            union_labels.insert(faces.begin(), faces.end());
            CHECK(fs::exists(dir / "textured" / "mesh.obj") == !wide);
        }
        CHECK(tiled_report.getJson({"tiles", name, "faces"}) == std::to_string(mesh.n_faces()));
    }
    // The same surface: every face of the untiled mesh in exactly one tile, nothing else.
    CHECK(union_mesh.size() == reference.size());
    CHECK(union_mesh == reference);
    CHECK(face_sum == untiled_mesh.n_faces());
    CHECK(index["counts"]["faces"].get<std::size_t>() == untiled_mesh.n_faces());

    // Labels: MRF on core + halo per tile; agreement with the one global MRF on the faces a
    // semantic view sees (unseen faces are filled by the MRF from whatever it reaches).
    DatasetConfig dataset_config;
    dataset_config.path = (root / "seq").string();
    const auto dataset = Dataset::open(dataset_config, root);
    VisibilityOptions vis_options;
    vis_options.max_view_angle_deg = 88;
    const Raycaster raycaster = Raycaster::fromMesh(untiled_semantic);
    const Visibility vis = computeVisibility(untiled_semantic, datasetViews(*dataset, false, true),
                                             vis_options, &raycaster);
    const auto seen_faces = labelledFaces(untiled_semantic, nullptr);
    std::set<Face> seen;
    {
        std::size_t i = 0;
        for (const auto fh : untiled_semantic.faces()) {
            (void)i;
            if (vis.count(static_cast<std::size_t>(fh.idx())) == 0) continue;
            Face f{};
            int k = 0;
            for (const auto vh : untiled_semantic.fv_range(fh)) {
                const auto p = untiled_semantic.point(vh);
                f[static_cast<std::size_t>(k++)] = {p[0], p[1], p[2]};
            }
            std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
            seen.insert(f);
        }
    }
    REQUIRE(seen.size() > 1000);
    std::size_t same = 0, compared = 0, same_all = 0;
    for (const auto& [face, label] : union_labels) {
        const auto it = reference_labels.find(face);
        REQUIRE(it != reference_labels.end());
        same_all += it->second == label ? 1 : 0;
        if (seen.count(face) == 0) continue;
        ++compared;
        same += it->second == label ? 1 : 0;
    }
    INFO("all faces: " << same_all << " of " << union_labels.size() << " agree");
    CHECK(compared == seen.size());  // every seen face is in some tile's semantic output
    CHECK(static_cast<double>(same) / static_cast<double>(compared) >= min_agreement);
    CHECK(tiled_report.getJson({"tiling", "tiles"}) == std::to_string(tiles.size()));
    CHECK(tiled_report.getJson({"status", "state"}) == "\"done\"");
}

TEST_CASE("A streamed tiled run finishes tiles before the last scan, with the same outputs",
          "[tiles][pipeline][stream][heavy]") {
    // 60 m of street in 12 frames; a 20 m range filter makes the tiles near the start
    // unreachable by the later scans, so they can be finished early.
    const fs::path root = streetRoot("stream", 12, 60.0);
    const std::string tiling = "tiling: {tile_size_m: 6.4, halo_m: 1, occluder_margin_m: 3, "
                               "max_view_distance_m: 20";
    const std::string dataset = ", max_range_m: 20";
    Report streamed_report, whole_report;
    fs::remove_all(root / "streamed");
    fs::remove_all(root / "whole");
    Pipeline::fromString(streetYaml("", tiling + "}\n", dataset), "streamed", root)
        ->run(root / "streamed", streamed_report, true);
    Pipeline::fromString(streetYaml("", tiling + ", stream: false}\n", dataset), "whole", root)
        ->run(root / "whole", whole_report, true);

    // Every tile file and the index are byte for byte those of the unstreamed run.
    const auto streamed = filesBelow(root / "streamed" / "tiles");
    const auto whole = filesBelow(root / "whole" / "tiles");
    REQUIRE(streamed.size() > 20);
    CHECK(streamed.size() == whole.size());
    for (const auto& [file, bytes] : whole) {
        INFO(file);
        REQUIRE(streamed.count(file) == 1);
        CHECK(streamed.at(file) == bytes);
    }
    const std::string index_a = readText(root / "streamed" / "tiles.json");
    CHECK(index_a == readText(root / "whole" / "tiles.json"));
    // One map.vdb of the whole map, the same voxels.
    CHECK(vdbVoxels(root / "streamed" / "map.vdb") == vdbVoxels(root / "whole" / "map.vdb"));

    // Tiles were finished while scans were still coming in, each after every scan that can
    // reach it and every view that may see it.
    const nlohmann::json index = nlohmann::json::parse(index_a);
    const nlohmann::json report = nlohmann::json::parse(streamed_report.toJson());
    DatasetConfig dataset_config;
    dataset_config.path = (root / "seq").string();
    const auto ds = Dataset::open(dataset_config, root);
    const std::vector<View> views = datasetViews(*ds, false, false);
    const std::size_t last = ds->numFrames() - 1;
    std::size_t early = 0;
    for (const auto& tile : index["tiles"]) {
        const std::string name = tile["name"];
        INFO("tile " << name);
        const long after = report["tiles"][name]["finished_after_frame"];
        CHECK(nlohmann::json::parse(whole_report.toJson())["tiles"][name]["finished_after_frame"] ==
              static_cast<long>(last));
        early += after < static_cast<long>(last) ? 1 : 0;
        Box3d halo;
        for (int k = 0; k < 3; ++k) {
            halo.min_W[k] = tile["halo_bounds_W"]["min"][k];
            halo.max_W[k] = tile["halo_bounds_W"]["max"][k];
        }
        for (const View& v : views) {
            if (viewFrustumMeetsBox(v, halo, 0.0, 20.0)) CHECK(static_cast<long>(v.frame) <= after);
        }
    }
    CHECK(early >= 3);
    CHECK(report["tiling"]["stream"] == true);
    CHECK(report["status"]["state"] == "done");
}

TEST_CASE("A failing tile fails the run, names the tile and leaves no tiles.json",
          "[tiles][pipeline]") {
    const fs::path root = streetRoot("failing");
    const fs::path out = root / "failing";
    fs::create_directories(out);
    std::ofstream(out / "tiles.json") << "{\"stale\": true}";  // an earlier run's index
    const std::string yaml = streetYaml("    label_grid: true\n",
                                        "tiling: {tile_size_m: 12.8, halo_m: 1}\n");
    Report report;
    auto pipeline = Pipeline::fromString(yaml, "failing", root);
    try {
        pipeline->run(out, report, true);
        FAIL("the run should fail");
    } catch (const Error& e) {
        const std::string what = e.what();
        CHECK(what.rfind("tile ", 0) == 0);
        CHECK(what.find("semantic.mrf") != std::string::npos);
        CHECK(what.find("label_grid") != std::string::npos);
        CHECK(exitCodeFor(e) == 1);
    }
    CHECK_FALSE(fs::exists(out / "tiles.json"));
    CHECK(fs::exists(out / "report.json"));
    CHECK(report.getJson({"status", "state"}) == "\"failed\"");
}

TEST_CASE("tiling: config errors name the key and the value", "[tiles][yaml]") {
    const std::string stages =
        "dataset: {format: kitti, path: seq}\n"
        "stages:\n  - stage: integrate.atsdf\n    voxel_size_m: 0.1\n  - stage: mesh.marching_cubes\n";
    auto error = [&](const std::string& tiling, const std::vector<std::string>& set = {}) {
        try {
            Pipeline::fromString(stages + tiling, "t.yaml", ".", set);
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    std::string e = error("tiling: {tile_size_m: 0.5}\n");  // < 8 voxels of 0.1 m
    CHECK(e.find("tile_size_m") != std::string::npos);
    CHECK(e.find("0.5") != std::string::npos);
    CHECK(e.find("t.yaml") != std::string::npos);
    e = error("tiling: {tile_size_m: 64, halo_m: -1}\n");
    CHECK(e.find("halo_m") != std::string::npos);
    CHECK(e.find("-1") != std::string::npos);
    e = error("tiling: {tile_size_m: 64, up_axis: w}\n");
    CHECK(e.find("up_axis") != std::string::npos);
    e = error("tiling: {tile_size_m: 64, no_such: 1}\n");
    CHECK(e.find("no_such") != std::string::npos);
    e = error("", {"tiling.tile_size_m=0.2"});
    CHECK(e.find("tile_size_m") != std::string::npos);
    CHECK(error("tiling: {tile_size_m: 0.8, halo_m: 0}\n") == "no error");
    CHECK(error("tiling: {tile_size_m: 0}\n") == "no error");  // untiled
}

TEST_CASE("View frustum test against boxes", "[tiles][render]") {
    View view;  // camera at the origin looking along +z (T_C_W = identity)
    view.intrinsics.width = 100;
    view.intrinsics.height = 50;
    view.intrinsics.fx = view.intrinsics.fy = 50;
    view.intrinsics.cx = 49.5;
    view.intrinsics.cy = 24.5;
    auto box = [](double x0, double y0, double z0, double x1, double y1, double z1) {
        Box3d b;
        b.min_W = {x0, y0, z0};
        b.max_W = {x1, y1, z1};
        return b;
    };
    CHECK(viewMaySeeBox(view, box(-1, -1, 5, 1, 1, 6), 0.1, 100));      // straight ahead
    CHECK_FALSE(viewMaySeeBox(view, box(-1, -1, -6, 1, 1, -5), 0.1, 100));  // behind
    CHECK_FALSE(viewMaySeeBox(view, box(-1, -1, 150, 1, 1, 160), 0.1, 100));  // too far
    CHECK_FALSE(viewMaySeeBox(view, box(20, -1, 5, 22, 1, 6), 0.1, 100));  // right of the frustum
    CHECK(viewMaySeeBox(view, box(4, -1, 5, 22, 1, 6), 0.1, 100));    // straddles the border
    CHECK(viewMaySeeBox(view, box(-50, -50, -50, 50, 50, 50), 0.1, 100));  // contains the camera
    CHECK(viewDistanceToBox(view, box(3, 4, -1, 5, 6, 1)) == Approx(5.0));
    view.T_C_W = Isometry3d(Eigen::Translation3d(0, 0, 10));  // camera at z = -10 in W
    CHECK(viewMaySeeBox(view, box(-1, -1, -6, 1, 1, -5), 0.1, 100));
    // The frustum planes alone: depth (camera z) is what limits a face's visibility, so a box
    // off the axis within that depth but farther from the centre still meets the frustum.
    view.T_C_W = Isometry3d::Identity();
    CHECK(viewFrustumMeetsBox(view, box(8, -1, 9.5, 9, 1, 10), 0.1, 10));
    CHECK_FALSE(viewMaySeeBox(view, box(8, -1, 9.5, 9, 1, 10), 0.1, 10));  // 12.7 m away
    CHECK_FALSE(viewFrustumMeetsBox(view, box(8, -1, 10.5, 9, 1, 11), 0.1, 10));  // deeper
    CHECK_FALSE(viewFrustumMeetsBox(view, box(12, -1, 9.5, 13, 1, 10), 0.1, 10));  // outside
}
