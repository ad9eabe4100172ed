// SPDX-License-Identifier: Apache-2.0
#include "Tiles3dStage.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <system_error>

#include <time.h>

#include <nlohmann/json.hpp>
#include <tbb/parallel_pipeline.h>

#include "Lod.h"
#include "MeshDistance.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap::tiles3d {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr const char* kDir = "3dtiles";

/// CPU time of the calling thread, seconds (the leaf writer runs on one thread; tiles in
/// flight run on others, so the process's CPU time would count theirs).
double threadCpuTimeS() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

std::string readFile(const fs::path& path, const std::string& who) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(who + ": cannot read " + path.string());
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

json boundsJson(const Bounds& b) {
    return {{"min", {b.min_W.x(), b.min_W.y(), b.min_W.z()}},
            {"max", {b.max_W.x(), b.max_W.y(), b.max_W.z()}}};
}

Bounds boundsFromJson(const json& j) {
    Bounds b;
    b.add(Eigen::Vector3d(j.at("min").at(0), j.at("min").at(1), j.at("min").at(2)));
    b.add(Eigen::Vector3d(j.at("max").at(0), j.at("max").at(1), j.at("max").at(2)));
    return b;
}

/// The tile's core faces with their texture, class and confidence (from the mesh's
/// properties: texture.mrf and semantic.mrf leave them there).
TileMesh tileMeshFromContext(const Context& ctx) {
    const TriMesh& mesh = ctx.mesh();
    const std::vector<std::uint8_t> halo = ctx.haloFaces();
    TileMesh out;
    OpenMesh::FPropHandleT<std::uint8_t> label_prop;
    const bool has_labels = mesh.get_property_handle(label_prop, kFaceLabelProperty);
    OpenMesh::FPropHandleT<float> conf_prop;
    const bool has_conf = mesh.get_property_handle(conf_prop, kFaceLabelConfidenceProperty);
    OpenMesh::FPropHandleT<std::array<float, 6>> uv_prop;
    OpenMesh::FPropHandleT<int> page_prop;
    OpenMesh::MPropHandleT<std::vector<cv::Mat>> atlas_prop;
    const bool has_texture = mesh.get_property_handle(uv_prop, kFaceTextureUvProperty) &&
                             mesh.get_property_handle(page_prop, kFaceTexturePageProperty) &&
                             mesh.get_property_handle(atlas_prop, kMeshTextureAtlasProperty);
    if (has_texture) out.pages = mesh.property(atlas_prop);
    Bounds core;
    for (const auto fh : mesh.faces()) {
        if (halo[static_cast<std::size_t>(fh.idx())]) continue;
        for (const auto vh : mesh.fv_range(fh)) {
            const auto& p = mesh.point(vh);
            core.add(Eigen::Vector3d(p[0], p[1], p[2]));
        }
    }
    if (!core.empty()) out.origin_W = (0.5 * (core.min_W + core.max_W)).array().round().matrix();
    for (const auto fh : mesh.faces()) {
        if (halo[static_cast<std::size_t>(fh.idx())]) continue;
        std::array<Eigen::Vector3f, 3> c;
        std::size_t k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            const auto& p = mesh.point(vh);
            if (k < 3) c[k] = (Eigen::Vector3d(p[0], p[1], p[2]) - out.origin_W).cast<float>();
            ++k;
        }
        out.corners.push_back(c);
        out.label.push_back(has_labels ? mesh.property(label_prop, fh) : kUnknownLabel);
        out.confidence.push_back(has_conf ? mesh.property(conf_prop, fh) : 0.0f);
        std::uint32_t page = kNoPage;
        if (has_texture) {
            const int pg = mesh.property(page_prop, fh);
            if (pg >= 0 && static_cast<std::size_t>(pg) < out.pages.size()) page = static_cast<std::uint32_t>(pg);
            const std::array<float, 6>& uv = mesh.property(uv_prop, fh);
            // OBJ convention (v up) -> glTF (v down).
            out.uvs.push_back({Eigen::Vector2f(uv[0], 1.0f - uv[1]), Eigen::Vector2f(uv[2], 1.0f - uv[3]),
                               Eigen::Vector2f(uv[4], 1.0f - uv[5])});
        }
        out.page.push_back(page);
    }
    return out;
}

struct Node {
    int kx = 0, ky = 0;
    TileNode tile;
    std::string glb;  ///< file below the output folder ("" = no content)
    std::size_t faces = 0;
};

}  // namespace

void Tiles3dStage::declareOptions(OptionSpec& spec) {
    spec.add("image_format", "Atlas pages inside the GLBs: 'jpeg' or 'png'", image_format_,
             std::string("jpeg"));
    spec.add("jpeg_quality", "JPEG quality of the atlas pages, 1..100", jpeg_quality_, 90);
    spec.add("compression",
             "Vertex data: 'meshopt' (EXT_meshopt_compression, required by the GLB) or 'none' "
             "(plain glTF, e.g. for Blender)",
             compression_, std::string("meshopt"));
    spec.add("lod_levels",
             "Levels of simplified parents above the ground tiles (quadtree); -1 = up to one root "
             "for the whole drive, 0 = leaves only (their parents have no content)",
             lod_levels_, -1);
    spec.add("lod_atlas_max_px", "Largest atlas page side of a parent", lod_atlas_max_px_, 4096, "px");
    spec.add("lod_parents_in_flight",
             "Parents of a level built at once (each is parallel inside; memory grows with it), >= 1",
             lod_parents_in_flight_, 2);
    spec.add("labels_file",
             "Label set 'id, name, r g b' for the class table ('' = the dataset's or the "
             "docs/DATA.md default; use the same as semantic.mrf)",
             labels_file_, std::string());
    spec.add("georef", "Place W on the globe: root transform to ECEF (WGS84) from the georef_* keys",
             georef_, false);
    spec.add("georef_latitude_deg", "Latitude of W's origin (WGS84), [-90, 90]", latitude_deg_, 0.0, "deg");
    spec.add("georef_longitude_deg", "Longitude of W's origin (WGS84), [-180, 180]", longitude_deg_, 0.0, "deg");
    spec.add("georef_altitude_m", "Ellipsoidal height of W's origin, [-11000, 100000]", altitude_m_, 0.0, "m");
    spec.add("georef_heading_deg",
             "Compass heading of the z-up frame's +y axis (W's +y for a z-up W), clockwise from north, [-360, 360] (0: x east, y north)",
             heading_deg_, 0.0, "deg");
    spec.add("drive_path", "Also write 3dtiles/drive_path.json (the LiDAR positions in W)",
             drive_path_, true);
}

void Tiles3dStage::initialize() {
    auto range = [&](const char* key, double v, double lo, double hi) {
        if (!(v >= lo && v <= hi)) {
            std::ostringstream s;
            s << "option '" << key << "' must be in [" << lo << ", " << hi << "], got " << v;
            failConfig(s.str());
        }
    };
    if (image_format_ != "jpeg" && image_format_ != "png") {
        failConfig("option 'image_format' must be 'jpeg' or 'png', got '" + image_format_ + "'");
    }
    if (jpeg_quality_ < 1 || jpeg_quality_ > 100) {
        failConfig("option 'jpeg_quality' must be in [1, 100], got " + std::to_string(jpeg_quality_));
    }
    if (compression_ != "meshopt" && compression_ != "none") {
        failConfig("option 'compression' must be 'meshopt' or 'none', got '" + compression_ + "'");
    }
    if (lod_levels_ < -1) failConfig("option 'lod_levels' must be >= -1, got " + std::to_string(lod_levels_));
    if (lod_parents_in_flight_ < 1) {
        failConfig("option 'lod_parents_in_flight' must be >= 1, got " + std::to_string(lod_parents_in_flight_));
    }
    if (lod_atlas_max_px_ < 64 || lod_atlas_max_px_ > 16384) {
        failConfig("option 'lod_atlas_max_px' must be in [64, 16384], got " + std::to_string(lod_atlas_max_px_));
    }
    range("georef_latitude_deg", latitude_deg_, -90, 90);
    range("georef_longitude_deg", longitude_deg_, -180, 180);
    range("georef_altitude_m", altitude_m_, -11000, 100000);
    range("georef_heading_deg", heading_deg_, -360, 360);
}

void Tiles3dStage::declareLayers(LayerSpec& spec) const { spec.reads(layers::kMesh); }

GlbOptions Tiles3dStage::glbOptions() const {
    GlbOptions o;
    o.jpeg = image_format_ == "jpeg";
    o.jpeg_quality = jpeg_quality_;
    o.meshopt = compression_ == "meshopt";
    return o;
}

std::vector<ClassInfo> Tiles3dStage::classes(const Context& ctx) const {
    std::string file = labels_file_;
    if (file.empty() && ctx.hasDataset()) file = ctx.dataset().config().labels_file;
    LabelSet labels = LabelSet::defaults();
    if (!file.empty()) {
        fs::path path(file);
        if (path.is_relative() && !fs::exists(path) && ctx.hasDataset() &&
            fs::exists(ctx.dataset().root() / path)) {
            path = ctx.dataset().root() / path;
        }
        labels = LabelSet::fromFile(path);
    }
    std::vector<ClassInfo> out;
    for (const LabelClass& c : labels.classes()) out.push_back({c.id, c.name, c.rgb});
    if (labels.indexOf(kUnknownLabel) < 0) out.push_back({kUnknownLabel, "unknown", {0, 0, 0}});
    return out;
}

void Tiles3dStage::run(Context& ctx) {
    const std::string stage(name());
    if (ctx.hasTile()) {
        saw_tile_ = true;
    } else if (saw_tile_) {
        logInfo(stage + ": tiling.merge's pass over the whole map: no GLB (the tileset's leaves are the tiles')");
        return;
    }
    Timer timer;
    const double cpu_start_s = threadCpuTimeS();
    TileMesh mesh = tileMeshFromContext(ctx);
    if (mesh.faces() == 0) fail("the mesh has no faces to export");
    const std::vector<ClassInfo> table = classes(ctx);
    std::string glb;
    try {
        glb = writeGlb(mesh, table, glbOptions());
    } catch (const std::exception& e) {
        fail(std::string(kDir) + "/tile.glb: " + e.what());
    }
    const Bounds bounds = boundsW(mesh);
    const std::array<double, 256> areas = classAreas(mesh);
    json area = json::object();
    for (int id = 0; id < 256; ++id) {
        if (areas[static_cast<std::size_t>(id)] > 0) area[std::to_string(id)] = areas[static_cast<std::size_t>(id)];
    }
    int up_axis = 2;
    double voxel_size_m = 0.1;
    if (ctx.hasTile()) {
        up_axis = ctx.tile().up_axis;
        voxel_size_m = ctx.tile().voxel_size_m;
    } else {
        up_axis = TileGrid::resolveUpAxis(TilingConfig{}, ctx.hasDataset() ? &ctx.dataset() : nullptr);
        if (ctx.hasMap()) voxel_size_m = ctx.map().voxelSize();
    }
    // Up is +axis or -axis (KITTI's camera frame: y points down): the LiDAR's z at frame 0.
    int up_sign = 1;
    if (ctx.hasDataset() && ctx.dataset().numFrames() > 0 &&
        ctx.dataset().frame(0).T_W_L.rotation()(up_axis, 2) < 0) {
        up_sign = -1;
    }
    const json side = {{"faces", mesh.faces()},
                       {"bounds_W", boundsJson(bounds)},
                       {"up_axis", up_axis},
                       {"up_sign", up_sign},
                       {"voxel_size_m", voxel_size_m},
                       {"glb_bytes", glb.size()},
                       {"atlas_pages", mesh.pages.size()},
                       {"class_area_m2", area}};
    // The GLB first: a tile.json always describes a GLB that exists.
    ctx.writeOutput(fs::path(kDir) / "tile.glb", glb);
    ctx.writeOutput(fs::path(kDir) / "tile.json", side.dump(1));
    Report& report = ctx.report();
    report.stage(stage, "faces", mesh.faces());
    report.stage(stage, "glb_bytes", glb.size());
    report.stage(stage, "bytes_per_face", double(glb.size()) / double(mesh.faces()));
    report.stage(stage, "atlas_pages", mesh.pages.size());
    report.stage(stage, "cpu_time_s", threadCpuTimeS() - cpu_start_s);
    logInfo(stage + ": " + std::to_string(mesh.faces()) + " faces, " + std::to_string(glb.size()) +
            " bytes in " + std::to_string(timer.elapsedSeconds()) + " s");
}

void Tiles3dStage::beginRun(Context& ctx) {
    // A tileset of an earlier run must not outlive a failure of this one; its parents are
    // rebuilt from the tiles.
    std::error_code ec;
    const fs::path dir = ctx.outputDir() / kDir;
    fs::remove(dir / "tileset.json", ec);
    fs::remove_all(dir / "lod", ec);
}

void Tiles3dStage::finishRun(Context& ctx, const std::vector<FinishedTile>& tiles) {
    if (ctx.process() != 0) return;
    const std::string stage(name());
    Timer timer;
    const double cpu_start_s = processCpuTimeS();  // only the parents run now
    const fs::path out = ctx.outputDir();
    const fs::path dir = out / kDir;

    // The leaves: one per finished tile (untiled: the run's own 3dtiles/tile.glb).
    std::vector<Node> level;
    int up_axis = 2, up_sign = 1;
    double voxel_size_m = 0.1;
    std::array<double, 256> area{};
    std::size_t leaf_faces = 0, leaf_bytes = 0;
    std::vector<FinishedTile> leaves = tiles;
    if (leaves.empty()) {
        leaves.push_back({"", 0, 0});
    } else {
        // A tiled run's leaves are its tiles': no run-level leaf (tiling.merge's pass on
        // --resume, or an earlier untiled run in this folder) stays beside them.
        std::error_code ec;
        fs::remove(dir / "tile.glb", ec);
        fs::remove(dir / "tile.json", ec);
    }
    int min_ix = leaves.front().ix, min_iy = leaves.front().iy;
    for (const FinishedTile& t : leaves) {
        min_ix = std::min(min_ix, t.ix);
        min_iy = std::min(min_iy, t.iy);
    }
    for (const FinishedTile& t : leaves) {
        const fs::path rel = t.name.empty() ? fs::path(kDir) : fs::path("tiles") / t.name / kDir;
        const fs::path side_path = out / rel / "tile.json";
        const std::string where = t.name.empty() ? "" : "tile " + t.name + ": ";
        if (!fs::exists(side_path) || !fs::exists(out / rel / "tile.glb")) {
            fail(where + (out / rel / "tile.glb").string() +
                 " is missing (is export.3dtiles after the mesh stages?)");
        }
        json side;
        try {
            side = json::parse(readFile(side_path, stage));
        } catch (const json::exception& e) {
            fail(where + side_path.string() + ": " + e.what());
        }
        Node n;
        n.kx = t.ix - min_ix;
        n.ky = t.iy - min_iy;
        n.glb = (rel / "tile.glb").generic_string();
        n.tile.box_W = boundsFromJson(side.at("bounds_W"));
        n.tile.geometric_error_m = 0.0;
        n.tile.content_uri = t.name.empty() ? "tile.glb" : "../tiles/" + t.name + "/" + kDir + "/tile.glb";
        n.faces = side.at("faces");
        up_axis = side.value("up_axis", 2);
        up_sign = side.value("up_sign", 1);
        voxel_size_m = side.value("voxel_size_m", 0.1);
        leaf_faces += n.faces;
        leaf_bytes += side.value("glb_bytes", 0u);
        for (const auto& [id, a] : side.at("class_area_m2").items()) {
            area[static_cast<std::size_t>(std::stoi(id))] += a.get<double>();
        }
        level.push_back(std::move(n));
    }

    // The quadtree: parents until one root.
    const std::vector<ClassInfo> table = classes(ctx);
    const GlbOptions glb_options = glbOptions();
    json levels = json::array();
    levels.push_back({{"level", 0}, {"tiles", level.size()}, {"faces", leaf_faces},
                      {"geometric_error_m", 0.0}});
    int depth = 0;
    double read_s = 0, build_s = 0, measure_s = 0, write_s = 0, weld_s = 0, simplify_s = 0, bake_s = 0;
    std::size_t distance_queries = 0;
    json level_times_s = json::array();  // the report's only: the tileset does not depend on time
    while (level.size() > 1) {
        ++depth;
        std::map<std::pair<int, int>, std::vector<Node>> groups;
        for (Node& n : level) groups[{n.ky >> 1, n.kx >> 1}].push_back(std::move(n));
        std::vector<Node> next;
        const bool content = lod_levels_ < 0 || depth <= lod_levels_;
        std::size_t faces = 0;
        double max_error = 0, level_texel_m = 0;
        std::size_t level_texels = 0, level_charts = 0;
        Timer level_timer;
        // Each parent's content (read, merge, simplify, bake, measure, write) is independent of
        // the others': up to lod_parents_in_flight of them at once, each parallel inside.
        struct Job {
            Node p;
            std::vector<Node> children;
            double child_error = 0;
            std::string file_name;
            bool build = false;
            ParentFigures pf;
            double d = 0, read_s = 0, build_s = 0, measure_s = 0, write_s = 0;
            std::size_t queries = 0;
        };
        std::vector<Job> jobs;
        for (auto& [key, children] : groups) {
            Job job;
            Node& p = job.p;
            p.ky = key.first;
            p.kx = key.second;
            p.tile.level = depth;
            for (const Node& c : children) {
                p.tile.box_W.add(c.tile.box_W);
                job.child_error = std::max(job.child_error, c.tile.geometric_error_m);
            }
            job.file_name = std::to_string(depth) + "_" + std::to_string(p.kx) + "_" + std::to_string(p.ky) + ".glb";
            job.build = content && std::all_of(children.begin(), children.end(), [](const Node& c) { return !c.glb.empty(); });
            job.children = std::move(children);
            jobs.push_back(std::move(job));
        }
        auto buildJob = [&](Job& job) {
            Timer step;
            std::vector<TileMesh> meshes;
            for (const Node& c : job.children) {
                try {
                    meshes.push_back(readGlb(readFile(out / c.glb, stage), (out / c.glb).string()));
                } catch (const std::exception& e) {
                    fail(std::string("level ") + std::to_string(depth) + " parent " + job.file_name + ": " + e.what());
                }
            }
            std::vector<const TileMesh*> ptrs;
            for (const TileMesh& m : meshes) ptrs.push_back(&m);
            ParentOptions po;
            po.level = depth;
            po.voxel_size_m = voxel_size_m;
            po.max_atlas_px = lod_atlas_max_px_;
            // The children's faces in W, in order: the bake's nearest points and the measured
            // bound both search them.
            std::vector<Triangle> reference;
            for (const TileMesh& m : meshes) {
                for (const auto& t : trianglesW(m)) reference.push_back(t);
            }
            const TriangleGrid grid(std::move(reference));
            job.read_s = step.elapsedSeconds();
            step.reset();
            TileMesh parent = buildParent(ptrs, po, &job.pf, &grid);
            job.build_s = step.elapsedSeconds();
            step.reset();
            // The measured bound: distance from the parent to its children, plus theirs.
            meshes.clear();
            // (The bake's largest texel distance is a distance from the parent's surface already
            // measured: no triangle within it plus the tolerance needs a split.)
            job.d = hausdorffBound(trianglesW(parent), grid, std::max(0.5 * voxel_size_m, 0.25 * job.child_error),
                                   &job.queries, job.pf.max_texel_distance_m);
            job.measure_s = step.elapsedSeconds();
            step.reset();
            job.p.faces = parent.faces();
            const fs::path rel = fs::path(kDir) / "lod" / job.file_name;
            std::string glb;
            try {
                glb = writeGlb(parent, table, glb_options);
            } catch (const std::exception& e) {
                fail(rel.string() + ": " + e.what());
            }
            writeFileAtomically(out / rel, glb);
            job.write_s = step.elapsedSeconds();
        };
        std::size_t next_job = 0;
        tbb::parallel_pipeline(
            static_cast<std::size_t>(lod_parents_in_flight_),
            tbb::make_filter<void, Job*>(tbb::filter_mode::serial_in_order,
                                         [&](tbb::flow_control& fc) -> Job* {
                                             while (next_job < jobs.size() && !jobs[next_job].build) ++next_job;
                                             if (next_job == jobs.size()) {
                                                 fc.stop();
                                                 return nullptr;
                                             }
                                             return &jobs[next_job++];
                                         }) &
                tbb::make_filter<Job*, void>(tbb::filter_mode::parallel, [&](Job* job) { buildJob(*job); }));
        for (Job& job : jobs) {
            Node& p = job.p;
            if (job.build) {
                level_texel_m = std::max(level_texel_m, job.pf.texel_m);
                level_texels += job.pf.texels;
                level_charts += job.pf.charts;
                read_s += job.read_s;
                build_s += job.build_s;
                weld_s += job.pf.weld_s;
                simplify_s += job.pf.simplify_s;
                bake_s += job.pf.bake_s;
                measure_s += job.measure_s;
                write_s += job.write_s;
                distance_queries += job.queries;
                p.tile.geometric_error_m = job.child_error + std::max(job.d, 1e-3);
                p.glb = (fs::path(kDir) / "lod" / job.file_name).generic_string();
                p.tile.content_uri = "lod/" + job.file_name;
                faces += p.faces;
            } else {
                // No content: showing nothing is at most the box's diagonal wrong.
                p.tile.geometric_error_m = std::max(job.child_error * 2.0 + 1e-3,
                                                    (p.tile.box_W.max_W - p.tile.box_W.min_W).norm());
            }
            max_error = std::max(max_error, p.tile.geometric_error_m);
            for (Node& c : job.children) p.tile.children.push_back(std::move(c.tile));
            next.push_back(std::move(p));
        }
        levels.push_back({{"level", depth}, {"tiles", next.size()}, {"faces", faces},
                          {"geometric_error_m", max_error}, {"content", content},
                          {"texel_m", level_texel_m}, {"texels", level_texels}, {"charts", level_charts}});
        level_times_s.push_back(level_timer.elapsedSeconds());
        level = std::move(next);
    }

    // drive_path.json for the viewer, then tileset.json, last and atomically.
    if (drive_path_ && ctx.hasDataset()) {
        const Dataset& dataset = ctx.dataset();
        json positions = json::array();
        for (std::size_t i = 0; i < dataset.numFrames(); ++i) {
            const Eigen::Vector3d t = dataset.frame(i).T_W_L.translation();
            positions.push_back({t.x(), t.y(), t.z()});
        }
        writeFileAtomically(dir / "drive_path.json",
                            json({{"frame", "W"}, {"units", "m"}, {"what", "LiDAR positions, one per frame"},
                                  {"positions_W", positions}}).dump());
    }
    json class_list = json::array();
    for (const ClassInfo& c : table) {
        class_list.push_back({{"id", c.id}, {"name", c.name}, {"color", {c.rgb[0], c.rgb[1], c.rgb[2]}},
                              {"area_m2", area[c.id]}});
    }
    Georef georef;
    georef.enabled = georef_;
    georef.latitude_deg = latitude_deg_;
    georef.longitude_deg = longitude_deg_;
    georef.altitude_m = altitude_m_;
    georef.heading_deg = heading_deg_;
    json extras = {{"frame", "W"},
                   {"units", "m"},
                   {"up_axis", up_axis},
                   {"up_sign", up_sign},
                   {"voxel_size_m", voxel_size_m},
                   {"classes", class_list},
                   {"levels", levels},
                   {"feature_ids", "_FEATURE_ID_0: face (property table 0 'face': class_id, confidence); "
                                   "_FEATURE_ID_1: class (property table 1 'semantic_class': class_id, name, color)"}};
    if (drive_path_ && ctx.hasDataset()) extras["drive_path"] = "drive_path.json";
    if (georef_) {
        extras["georef"] = {{"latitude_deg", latitude_deg_}, {"longitude_deg", longitude_deg_},
                            {"altitude_m", altitude_m_}, {"heading_deg", heading_deg_}};
    }
    const std::string tileset = tilesetJson(level.front().tile, rootTransform(georef, up_axis, up_sign), extras);
    writeFileAtomically(dir / "tileset.json", tileset);

    Report& report = ctx.report();
    report.stage(stage, "finish_run_s", timer.elapsedSeconds());
    report.stage(stage, "finish_run_cpu_s", processCpuTimeS() - cpu_start_s);
    report.stage(stage, "leaves", leaves.size());
    report.set({"stages", stage, "lod_timings_s", "read_children"}, read_s);
    report.set({"stages", stage, "lod_timings_s", "merge_simplify_bake"}, build_s);
    report.set({"stages", stage, "lod_timings_s", "weld"}, weld_s);
    report.set({"stages", stage, "lod_timings_s", "simplify"}, simplify_s);
    report.set({"stages", stage, "lod_timings_s", "bake"}, bake_s);
    report.set({"stages", stage, "lod_timings_s", "measure_error"}, measure_s);
    report.set({"stages", stage, "lod_timings_s", "encode_write"}, write_s);
    report.setJson({"stages", stage, "lod_timings_s", "levels"}, level_times_s.dump());
    report.stage(stage, "lod_distance_queries", distance_queries);
    report.stage(stage, "leaf_faces", leaf_faces);
    report.stage(stage, "leaf_glb_bytes", leaf_bytes);
    report.setJson({"stages", stage, "levels"}, levels.dump());
    report.set({"outputs", "tileset"}, (dir / "tileset.json").string());
    logInfo(stage + ": tileset.json with " + std::to_string(leaves.size()) + " leaves, " +
            std::to_string(depth) + " levels above them, in " + std::to_string(timer.elapsedSeconds()) + " s");
}

}  // namespace vdbmap::tiles3d
