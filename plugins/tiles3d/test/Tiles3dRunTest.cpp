// SPDX-License-Identifier: Apache-2.0
// export.3dtiles in real runs of the built `vdbmap` (issue 34) on a 40 m simulated street in 8
// frames with the texture and semantic stages:
//  - tiled (8 m tiles): the tileset's rules (child boxes inside parents, every content inside
//    its tile's box, geometricError decreasing downward, refine stated, every content exists);
//    each leaf GLB decodes to exactly the faces, classes and confidences of its tile's
//    semantic/mesh.ply; each parent's sampled distance to the leaves below it is at most its
//    geometricError;
//  - parents simplify: faces fall by 2x or more per level, their texel size doubles;
//  - tiling.merge writes no run-level GLB beside the tiles';
//  - untiled: one leaf, the same exactness;
//  - a tile worked in pieces (a memory budget below its estimate): each piece is a leaf, the
//    pieces of a tile below one parent, the rules above hold;
//  - a run killed after two tiles leaves no tileset.json; --resume ends with the uninterrupted
//    run's tileset.json and GLBs byte for byte;
//  - a latitude of 91 is a configuration error (exit 2) naming the key and the value.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>

#include "Bake.h"
#include "Glb.h"
#include "Lod.h"
#include "MeshDistance.h"
#include "support/CliRun.h"

namespace fs = std::filesystem;
using namespace vdbmap;
using namespace vdbmap::tiles3d;
using json = nlohmann::json;
using vdbmap::test::Child;
using vdbmap::test::ChildOptions;

namespace {

fs::path workDir() { return fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "tiles3d_run"; }

fs::path sequence() {
    const fs::path dir = workDir() / "seq";
    test::writeSimStreet(dir, 8, 40.0);
    return dir;
}

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

fs::path config(const std::string& name, bool tiled, const std::string& export_options = "",
                const std::string& tiling_options = "") {
    const fs::path seq = sequence();
    const fs::path file = workDir() / (name + "." + std::to_string(::getpid()) + ".yaml");
    std::ofstream out(file);
    out << "dataset: {format: kitti, path: " << seq.string() << ", max_range_m: 12}\n"
        << "plugins: [texture, semantic, tiles3d]\n"
        << "stages:\n"
        << "  - stage: integrate.atsdf\n    voxel_size_m: 0.2\n"
        << "  - stage: mesh.marching_cubes\n"
        << "  - stage: texture.mrf\n    max_view_angle_deg: 85\n"
        << "  - stage: semantic.mrf\n    max_view_angle_deg: 88\n"
        << "    lidar_labels: true\n    label_map: semantickitti\n"
        << "  - stage: export.3dtiles\n" << export_options;
    if (tiled) {
        out << "tiling: {tile_size_m: 8, halo_m: 1, occluder_margin_m: 3, max_view_distance_m: 20"
            << tiling_options << "}\n";
    }
    return file;
}

struct Run {
    int code = 0;
    std::string log;
};

Run run(const fs::path& cfg, const fs::path& out, std::vector<std::string> extra = {},
        ChildOptions options = {}) {
    std::vector<std::string> args{"run", cfg.string(), "-o", out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    Child child(test::kVdbmapExe, args, options);
    Run r;
    r.code = child.exitCode();
    r.log = child.log();
    return r;
}

/// A tiled run (with tiling.merge), made once per process.
const fs::path& tiledRun() {
    static const fs::path out = [] {
        const fs::path o = workDir() / ("tiled." + std::to_string(::getpid()));
        fs::remove_all(o);
        const Run r = run(config("tiled", true, "", ", merge: true"), o);
        INFO(r.log);
        REQUIRE(r.code == 0);
        return o;
    }();
    return out;
}

/// semantic/mesh.ply as vdbmap writes it (binary: x y z [nx ny nz], faces: uchar n + int
/// indices, uchar label, uchar rgb, float confidence): per face its corners, label, confidence.
struct PlyFaces {
    std::vector<std::array<Eigen::Vector3f, 3>> corners;
    std::vector<std::uint8_t> label;
    std::vector<float> confidence;
};

PlyFaces readSemanticPly(const fs::path& path) {
    const std::string bytes = readBytes(path);
    const std::size_t end = bytes.find("end_header\n");
    REQUIRE(end != std::string::npos);
    std::istringstream header(bytes.substr(0, end));
    std::string line, element;
    std::size_t nv = 0, nf = 0, vertex_bytes = 0;
    std::vector<std::string> face_props;
    while (std::getline(header, line)) {
        std::istringstream l(line);
        std::string w;
        l >> w;
        if (w == "element") {
            l >> element;
            (element == "vertex" ? nv : nf) = [&] { std::size_t n; l >> n; return n; }();
        } else if (w == "property" && element == "vertex") {
            std::string type;
            l >> type;
            vertex_bytes += type == "float" ? 4 : 1;
        } else if (w == "property" && element == "face") {
            std::string type, name;
            l >> type;
            if (type == "list") continue;
            l >> name;
            face_props.push_back(name);
        }
    }
    std::size_t at = end + 11;
    std::vector<Eigen::Vector3f> v(nv);
    for (std::size_t i = 0; i < nv; ++i) {
        std::memcpy(v[i].data(), bytes.data() + at, 12);
        at += vertex_bytes;
    }
    PlyFaces out;
    for (std::size_t f = 0; f < nf; ++f) {
        REQUIRE(static_cast<unsigned char>(bytes[at]) == 3);
        std::int32_t idx[3];
        std::memcpy(idx, bytes.data() + at + 1, 12);
        at += 13;
        out.corners.push_back({v[static_cast<std::size_t>(idx[0])], v[static_cast<std::size_t>(idx[1])], v[static_cast<std::size_t>(idx[2])]});
        for (const std::string& p : face_props) {
            if (p == "confidence") {
                float c;
                std::memcpy(&c, bytes.data() + at, 4);
                out.confidence.push_back(c);
                at += 4;
            } else {
                if (p == "label") out.label.push_back(static_cast<std::uint8_t>(bytes[at]));
                at += 1;
            }
        }
    }
    return out;
}

/// The GLB's faces equal the PLY's: same order, same corners (up to a rotation of the corner
/// order, within float rounding of the relative-to-centre offset), same class and confidence.
void requireSameFaces(const fs::path& glb, const fs::path& ply) {
    const TileMesh m = readGlb(readBytes(glb), glb.string());
    const PlyFaces p = readSemanticPly(ply);
    REQUIRE(m.faces() == p.corners.size());
    REQUIRE(m.faces() > 0);
    for (std::size_t f = 0; f < m.faces(); ++f) {
        bool match = false;
        for (int r = 0; r < 3 && !match; ++r) {
            match = true;
            for (int k = 0; k < 3; ++k) {
                const Eigen::Vector3d g = m.cornerW(f, (k + r) % 3);
                match = match && (g - p.corners[f][static_cast<std::size_t>(k)].cast<double>()).norm() < 1e-4;
            }
        }
        INFO("face " << f);
        REQUIRE(match);
        REQUIRE(m.label[f] == p.label[f]);
        REQUIRE(m.confidence[f] == p.confidence[f]);
    }
}

Bounds boxBounds(const json& tile) {
    const auto b = tile["boundingVolume"]["box"].get<std::vector<double>>();
    Bounds out;
    out.add(Eigen::Vector3d(b[0] - b[3], b[1] - b[7], b[2] - b[11]));
    out.add(Eigen::Vector3d(b[0] + b[3], b[1] + b[7], b[2] + b[11]));
    REQUIRE(b[4] == 0);  // axis-aligned half axes
    REQUIRE(b[8] == 0);
    return out;
}

/// Visits every tile with its parent (nullptr for the root).
void visit(const json& tile, const json* parent, const std::function<void(const json&, const json*)>& f) {
    f(tile, parent);
    if (tile.contains("children")) {
        for (const json& c : tile["children"]) visit(c, &tile, f);
    }
}

/// The 3D Tiles rules every tile of our tilesets keeps: REPLACE refinement, inside its parent's
/// box with a smaller geometric error, and its content (if any) inside its own box.
void checkTileRules(const json& tile, const json* parent, const fs::path& base) {
    CHECK(tile.value("refine", "") == "REPLACE");
    const Bounds box = boxBounds(tile);
    if (parent) {
        CHECK(boxBounds(*parent).contains(box, 1e-6));
        CHECK(tile["geometricError"].get<double>() < (*parent)["geometricError"].get<double>());
    }
    if (tile.contains("content")) {
        const fs::path file = base / tile["content"]["uri"].get<std::string>();
        REQUIRE(fs::exists(file));
        CHECK(box.contains(boundsW(readGlb(readBytes(file), file.string())), 1e-4));
    }
}

/// The leaves' triangles below `tile`.
void leafTriangles(const json& tile, const fs::path& base, std::vector<Triangle>& out) {
    if (!tile.contains("children") && tile.contains("content")) {
        for (const auto& t : trianglesW(readGlb(readBytes(base / tile["content"]["uri"].get<std::string>()), "leaf"))) out.push_back(t);
    }
    if (tile.contains("children")) {
        for (const json& c : tile["children"]) leafTriangles(c, base, out);
    }
}

}  // namespace

TEST_CASE("A tiled run's tileset follows the 3D Tiles rules; leaves are the semantic meshes",
          "[tiles3d][run]") {
    const fs::path out = tiledRun();
    const fs::path base = out / "3dtiles";
    const json tileset = json::parse(readBytes(base / "tileset.json"));
    CHECK(tileset["asset"]["version"] == "1.1");
    const json& root = tileset["root"];
    CHECK(tileset["geometricError"].get<double>() >= root["geometricError"].get<double>());
    // The simulator's KITTI W is camera 0's frame, y down: the root turns -y into z.
    REQUIRE(root.contains("transform"));
    const auto m = root["transform"].get<std::vector<double>>();  // column-major
    CHECK(m[4 * 0 + 2] == 0.0);  // x stays horizontal
    CHECK(m[4 * 1 + 2] == -1.0);  // W's y -> tileset -z
    CHECK(m[4 * 2 + 2] == 0.0);
    std::size_t leaves = 0, parents = 0;
    visit(root, nullptr, [&](const json& tile, const json* parent) {
        checkTileRules(tile, parent, base);
        if (!tile.contains("children")) {
            ++leaves;
            CHECK(tile["geometricError"].get<double>() == 0.0);
        } else {
            ++parents;
        }
    });
    std::size_t tile_dirs = 0;
    for (const auto& e : fs::directory_iterator(out / "tiles")) {
        ++tile_dirs;
        INFO(e.path());
        if (fs::exists(e.path() / "semantic" / "mesh.ply")) {
            requireSameFaces(e.path() / "3dtiles" / "tile.glb", e.path() / "semantic" / "mesh.ply");
        } else {  // semantic.mrf skipped the tile (nothing saw it): every face is unknown
            const TileMesh m = readGlb(readBytes(e.path() / "3dtiles" / "tile.glb"), "leaf");
            for (const std::uint8_t l : m.label) CHECK(l == 255);
        }
    }
    CHECK(leaves == tile_dirs);
    CHECK(leaves >= 4);
    CHECK(parents >= 2);
    // tiling.merge wrote the whole map's mesh, but no run-level GLB the tileset does not use.
    CHECK(fs::exists(out / "mesh.ply"));
    CHECK_FALSE(fs::exists(base / "tile.glb"));
    CHECK_FALSE(fs::exists(base / "tile.json"));
    // drive_path.json: one position per frame.
    const json path = json::parse(readBytes(base / "drive_path.json"));
    CHECK(path["positions_W"].size() == 8);
}

TEST_CASE("A tile worked in pieces: each piece a leaf below its tile's parent, the rules hold",
          "[tiles3d][run][split]") {
    // A budget just below the largest tile's estimate (tiling.memory_budget_gb, issue 37): that
    // tile is worked in pieces, tiles/<ix>_<iy>.<piece>/, which share the tile's (ix, iy).
    const fs::path reference = tiledRun();
    const json reference_report = json::parse(readBytes(reference / "report.json"));
    std::size_t largest = 0;
    for (const auto& [name, tile] : reference_report["tiles"].items()) {
        largest = std::max(largest, tile["memory_estimate_bytes"].get<std::size_t>());
    }
    REQUIRE(largest > (64u << 20) + (512u << 10));  // the budget above the estimate's fixed part
    const std::size_t budget_bytes = largest - (512u << 10);
    std::ostringstream budget;
    budget.precision(12);
    budget << ", memory_budget_gb: " << static_cast<double>(budget_bytes) / (1024.0 * 1024.0 * 1024.0);
    const fs::path out = workDir() / ("split." + std::to_string(::getpid()));
    fs::remove_all(out);
    const Run r = run(config("split", true, "", budget.str()), out);
    INFO(r.log);
    REQUIRE(r.code == 0);
    const json report = json::parse(readBytes(out / "report.json"));
    REQUIRE(report["tiling"]["split_tiles"].get<std::size_t>() >= 1);

    const fs::path base = out / "3dtiles";
    const json tileset = json::parse(readBytes(base / "tileset.json"));
    std::map<std::string, const json*> parent_of;  // leaf folder -> its parent in the tileset
    visit(tileset["root"], nullptr, [&](const json& tile, const json* parent) {
        checkTileRules(tile, parent, base);
        if (!tile.contains("children")) {
            REQUIRE(tile.contains("content"));
            const std::string uri = tile["content"]["uri"];  // ../tiles/<name>/3dtiles/tile.glb
            const std::string name = fs::path(uri).parent_path().parent_path().filename().string();
            CHECK(parent_of.emplace(name, parent).second);  // each leaf once
        }
    });
    // Every tile folder is a leaf (a piece's too), with its semantic mesh exactly; the pieces of
    // a tile hang below one parent, as the tile did.
    std::size_t tile_dirs = 0, pieces = 0;
    std::map<std::string, std::set<const json*>> parents_of_tile;
    for (const auto& e : fs::directory_iterator(out / "tiles")) {
        ++tile_dirs;
        const std::string name = e.path().filename().string();
        INFO(name);
        REQUIRE(parent_of.count(name) == 1);
        const std::size_t dot = name.find('.');
        if (dot != std::string::npos) {
            ++pieces;
            parents_of_tile[name.substr(0, dot)].insert(parent_of[name]);
            CHECK_FALSE(fs::exists(out / "tiles" / name.substr(0, dot)));  // not also whole
        }
        if (fs::exists(e.path() / "semantic" / "mesh.ply")) {
            requireSameFaces(e.path() / "3dtiles" / "tile.glb", e.path() / "semantic" / "mesh.ply");
        }
    }
    CHECK(parent_of.size() == tile_dirs);
    CHECK(pieces >= 2);
    for (const auto& [tile, parents] : parents_of_tile) {
        INFO(tile);
        CHECK(parents.size() == 1);
    }
    fs::remove_all(out);
}

TEST_CASE("Parents simplify: faces fall by at least 2x per level, texels grow 2x per level",
          "[tiles3d][run]") {
    const fs::path base = tiledRun() / "3dtiles";
    const json tileset = json::parse(readBytes(base / "tileset.json"));
    // Faces and texel size per level, counted from the GLBs themselves.
    std::map<int, std::size_t> faces;
    std::map<int, double> texel_min, texel_max;
    std::function<int(const json&)> height = [&](const json& tile) {
        int h = 0;
        if (tile.contains("children")) {
            for (const json& c : tile["children"]) h = std::max(h, height(c) + 1);
        }
        if (tile.contains("content")) {
            const TileMesh m = readGlb(readBytes(base / tile["content"]["uri"].get<std::string>()), "tile");
            faces[h] += m.faces();
            if (h > 0) {  // leaves' atlases are texture.mrf's
                const double t = texelSizeM(m);
                texel_min[h] = texel_min.count(h) ? std::min(texel_min[h], t) : t;
                texel_max[h] = std::max(texel_max[h], t);
            }
        }
        return h;
    };
    const int levels = height(tileset["root"]);
    REQUIRE(levels >= 2);
    for (int l = 1; l <= levels; ++l) {
        INFO("level " << l << ": " << faces[l] << " faces, level " << l - 1 << ": " << faces[l - 1]);
        CHECK(faces[l] > 0);
        CHECK(2 * faces[l] <= faces[l - 1]);
        if (l >= 2) {  // the texel size doubles (more where a page reached lod_atlas_max_px)
            CHECK(texel_min[l] >= 1.9 * texel_min[l - 1]);
        }
    }
}

TEST_CASE("Each parent's distance to the full-resolution mesh is at most its geometricError",
          "[tiles3d][run][heavy]") {
    const fs::path base = tiledRun() / "3dtiles";
    const json tileset = json::parse(readBytes(base / "tileset.json"));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    std::size_t checked = 0;
    visit(tileset["root"], nullptr, [&](const json& tile, const json*) {
        if (!tile.contains("children") || !tile.contains("content")) return;
        std::vector<Triangle> full;
        leafTriangles(tile, base, full);
        const TriangleGrid grid(full);
        const auto parent = trianglesW(readGlb(readBytes(base / tile["content"]["uri"].get<std::string>()), "parent"));
        double worst = 0;
        for (const Triangle& t : parent) {  // every corner, every centroid, random points
            for (const auto& q : {t[0], t[1], t[2], Eigen::Vector3d((t[0] + t[1] + t[2]) / 3.0)}) worst = std::max(worst, grid.distance(q));
            double r1 = u(rng), r2 = u(rng);
            if (r1 + r2 > 1) { r1 = 1 - r1; r2 = 1 - r2; }
            worst = std::max(worst, grid.distance(t[0] + r1 * (t[1] - t[0]) + r2 * (t[2] - t[0])));
        }
        INFO(tile["content"]["uri"] << ": sampled " << worst << " m, geometricError " << tile["geometricError"]);
        CHECK(worst <= tile["geometricError"].get<double>());
        ++checked;
    });
    CHECK(checked >= 2);
}

TEST_CASE("An untiled run is one leaf: the semantic mesh exactly", "[tiles3d][run]") {
    const fs::path out = workDir() / ("untiled." + std::to_string(::getpid()));
    fs::remove_all(out);
    const Run r = run(config("untiled", false, "    compression: none\n    image_format: png\n"), out);
    INFO(r.log);
    REQUIRE(r.code == 0);
    const json tileset = json::parse(readBytes(out / "3dtiles" / "tileset.json"));
    CHECK(tileset["root"]["content"]["uri"] == "tile.glb");
    CHECK(!tileset["root"].contains("children"));
    requireSameFaces(out / "3dtiles" / "tile.glb", out / "semantic" / "mesh.ply");
    GlbInfo info;
    readGlb(readBytes(out / "3dtiles" / "tile.glb"), "tile.glb", &info);
    CHECK(!info.meshopt);
    CHECK(info.image_mime_types == std::vector<std::string>{"image/png"});
    fs::remove_all(out);
}

TEST_CASE("A killed run leaves no tileset; --resume writes the uninterrupted run's bytes",
          "[tiles3d][run]") {
    const fs::path reference = tiledRun();
    const fs::path out = workDir() / ("killed." + std::to_string(::getpid()));
    fs::remove_all(out);
    fs::create_directories(out / "3dtiles");
    std::ofstream(out / "3dtiles" / "tileset.json") << "{\"stale\": true}";  // an earlier run's
    ChildOptions kill;
    kill.env = {{"VDBMAP_TEST_KILL_AFTER_TILES", "2"}};
    const Run killed = run(config("tiled", true), out, {}, kill);
    REQUIRE(killed.code != 0);
    CHECK(!fs::exists(out / "3dtiles" / "tileset.json"));
    CHECK(fs::exists(out / "tiles"));
    const Run resumed = run(config("tiled", true), out, {"--resume"});
    INFO(resumed.log);
    REQUIRE(resumed.code == 0);
    CHECK(readBytes(out / "3dtiles" / "tileset.json") == readBytes(reference / "3dtiles" / "tileset.json"));
    for (const auto& e : fs::recursive_directory_iterator(reference / "3dtiles" / "lod")) {
        if (!e.is_regular_file()) continue;
        CHECK(readBytes(e.path()) == readBytes(out / fs::relative(e.path(), reference)));
    }
    fs::remove_all(out);
}

TEST_CASE("A geo-reference out of range is a configuration error naming key and value",
          "[tiles3d][run]") {
    const fs::path out = workDir() / ("badgeo." + std::to_string(::getpid()));
    const Run r = run(config("badgeo", false, "    georef: true\n    georef_latitude_deg: 91\n"), out);
    CHECK(r.code == 2);
    CHECK_THAT(r.log, Catch::Contains("georef_latitude_deg") && Catch::Contains("91"));
    fs::remove_all(out);
}

#ifdef VDBMAP_MPIEXEC
TEST_CASE("Under vdbmap-mpi -np 2 the tileset is byte-identical to the single-process run's",
          "[tiles3d][run][mpi][heavy]") {
    const fs::path reference = tiledRun();
    const fs::path out = workDir() / ("mpi." + std::to_string(::getpid()));
    fs::remove_all(out);
    ChildOptions env;
    env.env = {{"OMPI_ALLOW_RUN_AS_ROOT", "1"}, {"OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1"}};
    if (const char* asan = std::getenv("ASAN_OPTIONS")) {
        env.env.emplace_back("ASAN_OPTIONS", std::string(asan) + ":detect_leaks=0");
    }
    Child child(VDBMAP_MPIEXEC, {"--oversubscribe", "-np", "2",
                                 (fs::path(VDBMAP_BINARY_DIR) / "bin" / "vdbmap-mpi").string(), "run",
                                 config("tiled", true).string(), "-o", out.string(), "--quiet"},
                env);
    const int code = child.exitCode();
    INFO(child.log());
    REQUIRE(code == 0);
    CHECK(readBytes(out / "3dtiles" / "tileset.json") == readBytes(reference / "3dtiles" / "tileset.json"));
    for (const auto& e : fs::recursive_directory_iterator(reference)) {
        if (e.is_regular_file() && e.path().extension() == ".glb") {
            INFO(e.path());
            CHECK(readBytes(e.path()) == readBytes(out / fs::relative(e.path(), reference)));
        }
    }
    fs::remove_all(out);
}
#endif
