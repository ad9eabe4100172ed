// SPDX-License-Identifier: Apache-2.0
#include "SemanticMrfStage.h"

#include <filesystem>

#include "GeometricSmoothness.h"
#include "LabelGrid.h"
#include "SemanticExport.h"
#include "SemanticFusion.h"
#include "SemanticRunReport.h"
#include "SemanticSources.h"
#include "TileFill.h"
#include "VoteCombination.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/mesh/TileFaces.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Tiling.h"
#include "vdbmap/render/VisibilitySetup.h"

namespace vdbmap::semantic {

namespace {

// World up: the mean z axis of the LiDAR poses (a vehicle's LiDAR is mounted level).
Vec3f worldUp(const Dataset& dataset) {
    Vec3d up = Vec3d::Zero();
    for (std::size_t i = 0; i < dataset.numFrames(); ++i) {
        up += dataset.frame(i).T_W_L.rotation().col(2);
    }
    return up.norm() > 0.0 ? Vec3f(up.normalized().cast<float>()) : Vec3f::UnitZ();
}

// Phase 1: the sources (image votes, LiDAR votes), combined into one distribution per face.
struct Sources {
    ImageVotes images;
    LidarVoteResult lidar;
    FaceVotes votes;                    // combined
    std::vector<std::uint8_t> sources;  // kSourceImages | kSourceLidar per face
};

Sources gatherSources(const std::string& stage, Context& ctx, const SemanticOptions& opt,
                      const FaceArrays& faces, const LabelSet& labels) {
    Sources s;
    if (opt.image_votes) {
        s.images = imageVotes(stage, ctx, opt.visibility, labels, opt.image_chunk,
                              opt.scan_occlusion ? &opt.scan : nullptr, opt.image_masks,
                              opt.image_masks_dilate_px);
    }
    if (opt.lidar_labels) {
        s.lidar = lidarVotes(stage, ctx, faces, labels, opt.label_map, opt.lidar_vote_radius_m);
    }
    s.votes = combineVotes(s.images.votes, s.lidar.votes, opt.lidar_weight, &s.sources);
    s.images.votes = FaceVotes();  // the combined votes are all that is needed from here on
    s.lidar.votes = FaceVotes();
    return s;
}

// Phase 2: MRF fusion with the geometry-aware (or the paper's uniform) smoothness.
FusionResult fuse(const TriMesh& mesh, const Dataset& dataset, const SemanticOptions& opt,
                  const FaceArrays& faces, const FaceVotes& votes, const LabelSet& labels) {
    FusionOptions fusion;
    fusion.lambda = opt.lambda;
    fusion.probability_floor = opt.probability_floor;
    fusion.all_classes = opt.all_classes;
    fusion.max_sweeps = opt.max_sweeps;
    const auto adjacency = faceAdjacency(mesh);
    std::vector<float> edge_weights;
    if (opt.fill == "geometric") {
        GeometricSmoothnessOptions geo;
        geo.normal_sigma_deg = opt.fill_normal_sigma_deg;
        geo.height_sigma_m = opt.fill_height_sigma_m;
        edge_weights = geometricEdgeWeights(faces.vertices, faces.triangles, adjacency,
                                            worldUp(dataset), geo);
        // The fill only: between two observed faces the paper's uniform Potts term stays.
        uniformBetweenObserved(edge_weights, adjacency, votes);
        fusion.edge_weights = &edge_weights;
    }
    return fuseLabels(votes, adjacency, labels, fusion);
}

// Phase 3: the exports; a tile writes its core faces only (the halo took part in the MRF).
void writeLabelledMesh(const Context& ctx, const SemanticOptions& opt, const TriMesh& mesh,
                       const FusionResult& result, const LabelSet& labels) {
    const std::filesystem::path dir = ctx.outputDir() / opt.output_subdir;
    std::filesystem::create_directories(dir);
    std::vector<std::uint32_t> core_faces;
    const TriMesh core = ctx.hasTile() ? coreSubmesh(mesh, &core_faces) : TriMesh();
    const TriMesh& out_mesh = ctx.hasTile() ? core : mesh;
    std::vector<std::uint8_t> out_labels;
    std::vector<float> out_confidence;
    for (const std::uint32_t f : core_faces) {
        out_labels.push_back(result.face_labels[f]);
        out_confidence.push_back(result.confidence[f]);
    }
    const std::vector<std::uint8_t>& written = ctx.hasTile() ? out_labels : result.face_labels;
    const std::vector<float>& confidence = ctx.hasTile() ? out_confidence : result.confidence;
    writeSemanticPly(dir / "mesh.ply", out_mesh, written, labels, &confidence);
    if (opt.write_obj) writeSemanticObj(dir / "mesh.obj", out_mesh, written, labels);
    for (const int id : opt.export_classes) {
        const auto cls = static_cast<std::uint8_t>(id);
        writeMeshPly(dir / classMeshFileName(cls, labels), extractClassMesh(out_mesh, written, cls));
    }
}

// Phase 3b: the optional "label" grid of map.vdb (untiled runs only: map.vdb is one file).
void writeLabelGrid(const std::string& stage, Context& ctx, const SemanticOptions& opt,
                    const TriMesh& mesh, const FusionResult& result) {
    if (!ctx.hasMap()) failIn(stage, "option 'label_grid' needs a map (an integrate stage before)");
    if (ctx.hasTile()) {
        failIn(stage, "option 'label_grid' is not available in tiled runs yet (map.vdb is one "
                      "file; the tiles would overwrite each other's grid)");
    }
    VoxelMap& map = ctx.map();
    map.setExtraGrid(grids::kLabel, labelGrid(mesh, result.face_labels, *map.transform(),
                                              static_cast<float>(opt.label_grid_band_vox)));
}

}  // namespace

void SemanticMrfStage::declareOptions(OptionSpec& spec) {
    spec.add("lambda", "Weight of the Potts smoothness between adjacent faces; 0 = naive voting",
             opt_.lambda, 0.5);
    spec.add("probability_floor", "Data cost is -log(max(p, floor)) of the normalised votes",
             opt_.probability_floor, 1e-3);
    spec.add("all_classes",
             "Observed faces may take unvoted classes (at the floor cost), not only voted ones",
             opt_.all_classes, false);
    spec.add("max_sweeps", "Alpha-expansion sweeps over all classes at most", opt_.max_sweeps, 5);
    spec.add("max_view_angle_deg", "Reject views seeing a face flatter than this",
             opt_.visibility.max_view_angle_deg, 80.0, "deg");
    spec.add("min_depth_m", "Nearest visible depth", opt_.visibility.min_depth_m, 0.1, "m");
    spec.add("max_depth_m",
             "Farthest visible depth (40 m: about 2 px per 10 cm face at KITTI's focal "
             "length; nearer views win anyway, and the views per face, so the cost per metre "
             "of drive, stay bounded)",
             opt_.visibility.max_depth_m, 40.0, "m");
    spec.add("occlusion_test", "Test occlusion by the mesh itself (Embree BVH)",
             opt_.visibility.occlusion_test, true);
    spec.add("occlusion_tolerance_m", "A hit closer than this to the face is no occluder",
             opt_.visibility.occlusion_tolerance_m, 0.02, "m");
    spec.add("scan_occlusion",
             "A view does not vote for a face that a return of the LiDAR scan nearest in time to "
             "its image hides (a moving car, anything in front that the map lacks)",
             opt_.scan_occlusion, true);
    spec.add("scan_occlusion_margin_m",
             "Scan occlusion: a return hides a face at depth z when nearer than "
             "z * (1 - scan_occlusion_margin_rel) - this",
             opt_.scan.margin_m, 0.3, "m");
    spec.add("scan_occlusion_margin_rel", "Scan occlusion: relative depth margin (see _margin_m)",
             opt_.scan.margin_rel, 0.1);
    spec.add("scan_occlusion_dilate_px",
             "Scan occlusion: radius of the min filter along image rows that closes the gaps "
             "between a ring's returns",
             opt_.scan.row_dilate_px, 2, "px");
    spec.add("scan_occlusion_gap_px",
             "Scan occlusion: the empty pixels of a column between two returns at most this many "
             "empty rows apart take the farther return (the gap between two rings)",
             opt_.scan.gap_px, 8, "px");
    spec.add("scan_occlusion_moving_margin_m",
             "Scan occlusion: a return removed as moving (integrate.atsdf dynamic_removal) hides "
             "a face at depth z when nearer than z - this (it cannot be the face itself)",
             opt_.scan.moving_margin_m, 0.1, "m");
    spec.add("scan_occlusion_moving_dilate_px",
             "Scan occlusion: radius of the min filter over the moving returns",
             opt_.scan.moving_dilate_px, 6, "px");
    spec.add("image_masks",
             "Folder of per-image masks (8-bit grey, named like the colour image, in "
             "<folder>/<camera> with several cameras): a view does not vote for a face that "
             "touches a non-zero pixel of its mask (texture.mrf's option; '' = no masks)",
             opt_.image_masks, std::string());
    spec.add("image_masks_dilate_px", "Image masks: grown by this radius before the test",
             opt_.image_masks_dilate_px, 2, "px");
    spec.add("labels_file",
             "Label set file 'id, name, r g b' (overrides the dataset's; '' = dataset's or the "
             "docs/DATA.md default)",
             opt_.labels_file, std::string());
    spec.add("export_classes", "Class ids also written as their own mesh (class_<id>_<name>.ply)",
             opt_.export_classes, std::vector<int>{});
    spec.add("label_grid",
             "Write a float grid 'label' into map.vdb: class of the nearest face per voxel",
             opt_.label_grid, false);
    spec.add("label_grid_band_vox", "Half width of the label grid around the mesh",
             opt_.label_grid_band_vox, 2.0, "voxels");
    spec.add("output_subdir", "Folder below the output folder for mesh.ply / mesh.obj",
             opt_.output_subdir, std::string("semantic"));
    spec.add("write_obj", "Also write mesh.obj + mesh.mtl with one material per class",
             opt_.write_obj, true);
    spec.add("image_chunk", "Semantic images held in memory at once", opt_.image_chunk, 64);
    spec.add("image_votes", "Votes from the semantic images (semantic_2/3, semantic_dir)",
             opt_.image_votes, true);
    spec.add("lidar_labels",
             "Votes from per-point LiDAR labels (KITTI SEQ/labels, generic labels_dir)",
             opt_.lidar_labels, false);
    spec.add("label_map",
             "LiDAR label ids -> label set: 'semantickitti' (built in, = "
             "config/label_maps/semantickitti.txt), a file of 'source target' lines, or '' "
             "(the ids are the label set's)",
             opt_.label_map, std::string());
    spec.add("lidar_weight", "Weight w_L of the LiDAR distribution against the images' in E_D",
             opt_.lidar_weight, 1.0);
    spec.add("lidar_vote_radius_m", "A labelled point votes for the faces closer than this",
             opt_.lidar_vote_radius_m, 0.1, "m");
    spec.add("fill",
             "Fill of faces no source saw: 'geometric' (the Potts weight of an edge next to such "
             "a face falls across normal changes and height steps) or 'uniform' (the paper: "
             "all weights 1)",
             opt_.fill, std::string("geometric"));
    spec.add("fill_normal_sigma_deg", "geometric fill: angle scale of the edge weight",
             opt_.fill_normal_sigma_deg, 20.0, "deg");
    spec.add("fill_height_sigma_m", "geometric fill: height-step scale of the edge weight",
             opt_.fill_height_sigma_m, 0.03, "m");
}

void SemanticMrfStage::initialize() {
    if (!(opt_.lambda >= 0.0)) failConfig("option 'lambda' must be >= 0, got " + std::to_string(opt_.lambda));
    if (!(opt_.probability_floor > 0.0 && opt_.probability_floor < 1.0)) {
        failConfig("option 'probability_floor' must be in (0, 1), got " +
                   std::to_string(opt_.probability_floor));
    }
    if (opt_.max_sweeps < 1) failConfig("option 'max_sweeps' must be >= 1, got " + std::to_string(opt_.max_sweeps));
    if (opt_.image_masks_dilate_px < 0 || opt_.image_masks_dilate_px > 32) {
        failConfig("option 'image_masks_dilate_px' must be in [0, 32], got " +
                   std::to_string(opt_.image_masks_dilate_px));
    }
    if (!opt_.image_masks.empty() && !std::filesystem::is_directory(opt_.image_masks)) {
        failConfig("option 'image_masks': '" + opt_.image_masks + "' is not a directory");
    }
    if (opt_.scan.margin_m < 0 || !(opt_.scan.margin_rel >= 0 && opt_.scan.margin_rel < 1) ||
        opt_.scan.row_dilate_px < 0 || opt_.scan.row_dilate_px > 32 || opt_.scan.gap_px < 0 ||
        opt_.scan.gap_px > 64) {
        failConfig("options 'scan_occlusion_margin_m' >= 0, 'scan_occlusion_margin_rel' in "
                   "[0, 1), 'scan_occlusion_dilate_px' in [0, 32] and 'scan_occlusion_gap_px' in "
                   "[0, 64], got " +
                   std::to_string(opt_.scan.margin_m) + ", " +
                   std::to_string(opt_.scan.margin_rel) + ", " +
                   std::to_string(opt_.scan.row_dilate_px) + ", " + std::to_string(opt_.scan.gap_px));
    }
    if (!(opt_.scan.moving_margin_m >= 0) || opt_.scan.moving_dilate_px < 0 || opt_.scan.moving_dilate_px > 32) {
        failConfig("options 'scan_occlusion_moving_margin_m' >= 0 and "
                   "'scan_occlusion_moving_dilate_px' in [0, 32], got " +
                   std::to_string(opt_.scan.moving_margin_m) + ", " +
                   std::to_string(opt_.scan.moving_dilate_px));
    }
    try {
        checkVisibilityOptions(opt_.visibility);
    } catch (const InvalidInput& e) {
        failConfig(e.what());
    }
    for (const int id : opt_.export_classes) {
        if (id < 0 || id > 254) {
            failConfig("option 'export_classes' holds " + std::to_string(id) +
                       "; class ids are 0..254");
        }
    }
    if (!(opt_.label_grid_band_vox >= 1.0)) {
        failConfig("option 'label_grid_band_vox' must be >= 1, got " +
                   std::to_string(opt_.label_grid_band_vox));
    }
    if (opt_.output_subdir.empty()) failConfig("option 'output_subdir' must not be empty");
    if (opt_.image_chunk < 1) failConfig("option 'image_chunk' must be >= 1, got " + std::to_string(opt_.image_chunk));
    if (!opt_.image_votes && !opt_.lidar_labels) {
        failConfig("options 'image_votes' and 'lidar_labels' are both false: no source to label from");
    }
    if (!(opt_.lidar_weight >= 0.0)) {
        failConfig("option 'lidar_weight' must be >= 0, got " + std::to_string(opt_.lidar_weight));
    }
    if (!(opt_.lidar_vote_radius_m > 0.0)) {
        failConfig("option 'lidar_vote_radius_m' must be > 0, got " +
                   std::to_string(opt_.lidar_vote_radius_m));
    }
    if (opt_.fill != "geometric" && opt_.fill != "uniform") {
        failConfig("option 'fill' must be 'geometric' or 'uniform', got '" + opt_.fill + "'");
    }
    if (!(opt_.fill_normal_sigma_deg > 0.0) || !(opt_.fill_height_sigma_m > 0.0)) {
        failConfig("options 'fill_normal_sigma_deg' and 'fill_height_sigma_m' must be > 0, got " +
                   std::to_string(opt_.fill_normal_sigma_deg) + " and " +
                   std::to_string(opt_.fill_height_sigma_m));
    }
}

void SemanticMrfStage::declareLayers(LayerSpec& spec) const {
    spec.reads(layers::kMesh);
    if (opt_.image_votes) spec.reads(layers::kSemanticImages);
    if (opt_.lidar_labels) spec.reads(layers::kScans);  // with their labels, from the dataset
    spec.writes(layers::kFaceLabels);
}


void SemanticMrfStage::run(Context& ctx) {
    TriMesh& mesh = ctx.mesh();
    const Dataset& dataset = ctx.dataset();
    const std::string stage(name());
    Timer total;
    if (mesh.n_faces() == 0) fail("the mesh has no faces: nothing to label");
    const LabelSet labels = loadLabelSet(stage, opt_.labels_file, dataset, opt_.export_classes);
    const FaceArrays faces = faceArrays(mesh);

    Sources sources = gatherSources(stage, ctx, opt_, faces, labels);
    if (sources.votes.numFaces() == 0 && ctx.hasTile()) {
        // A tile that no view sees and no labelled point reaches: nothing to label here.
        logInfo(stage + ": no source sees tile " + ctx.tile().name() + ": not labelled");
        ctx.report().stage(stage, "skipped", std::string("no view or labelled point sees the tile"));
        return;
    }

    Timer step;
    FusionResult result = fuse(mesh, dataset, opt_, faces, sources.votes, labels);
    SemanticRunFigures figures;
    figures.mrf_s = step.elapsedSeconds();
    // A tile: unobserved regions its halo cuts off from every observed face are labelled
    // from the tile grown by its occluder margin (TileFill.h).
    const TileFillWidening widened = fillFromWiderTile(ctx, result, [&](Context& wide) {
        const FaceArrays wide_faces = faceArrays(wide.mesh());
        const Sources s = gatherSources(stage, wide, opt_, wide_faces, labels);
        if (s.votes.numFaces() == 0) return std::vector<std::uint8_t>();
        return fuse(wide.mesh(), dataset, opt_, wide_faces, s.votes, labels).face_labels;
    });
    setFaceLabelProperty(mesh, result.face_labels);
    setFaceConfidenceProperty(mesh, result.confidence);

    step.reset();
    writeLabelledMesh(ctx, opt_, mesh, result, labels);
    if (opt_.label_grid) writeLabelGrid(stage, ctx, opt_, mesh, result);
    figures.export_s = step.elapsedSeconds();

    figures.faces = &faces;
    figures.images = &sources.images;
    figures.lidar = opt_.lidar_labels ? &sources.lidar : nullptr;
    figures.votes = &sources.votes;
    figures.sources = &sources.sources;
    figures.result = &result;
    figures.labels = &labels;
    figures.label_map = opt_.label_map;
    figures.fill = opt_.fill;
    figures.total_s = total.elapsedSeconds();
    reportSemanticRun(ctx.report(), stage, mesh, figures);
    if (ctx.hasTile()) {
        ctx.report().stage(stage, "widened_fill_faces", widened.faces_relabelled);
        ctx.report().stage(stage, "widened_fill_s", widened.seconds);
    }
}

}  // namespace vdbmap::semantic
