// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/sim/SimSequence.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <unordered_set>

#include "sim/SimImaging.h"
#include "sim/SimLidarLabels.h"
#include "sim/SimRigOutput.h"
#include "sim/SimTrafficFrame.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/eval/GtViews.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/io/PoseIO.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/TexturedRender.h"
#include "vdbmap/sim/LidarModel.h"
#include "vdbmap/sim/MoversJson.h"
#include "vdbmap/sim/Scenes.h"

namespace vdbmap {

namespace {

std::string frameName(std::size_t i) {
    std::ostringstream s;
    s << std::setw(6) << std::setfill('0') << i;
    return s.str();
}

void writeText(const std::filesystem::path& path, const std::string& text) {
    writeFileAtomically(path, text);  // checked to the last byte (a full disk is an IoError)
}

// KITTI's LiDAR -> camera-0 rotation (x_cam = -y_L, y_cam = -z_L, z_cam = x_L), a small
// extra rotation and an offset, so that a pipeline ignoring Tr builds a visibly wrong map.
Isometry3d simTr() {
    Eigen::Matrix3d R;
    R << 0, -1, 0, 0, 0, -1, 1, 0, 0;
    Isometry3d Tr = Isometry3d::Identity();
    Tr.linear() = Eigen::AngleAxisd(0.01, Vec3d::UnitX()).toRotationMatrix() * R;
    Tr.translation() = Vec3d(-0.004, -0.076, -0.272);
    return Tr;
}

// Baselines of KITTI cameras 0..3 in camera-0 coordinates: X_Ck = X_C0 + t_k.
Vec3d cameraOffset(int k) {
    switch (k) {
        case 1: return {-0.537, 0.0, 0.0};
        case 2: return {0.06, 0.0, 0.0};
        case 3: return {-0.47, 0.0, 0.0};
        default: return Vec3d::Zero();
    }
}

Mat34d projection(const CameraIntrinsics& K, const Vec3d& t) {
    Eigen::Matrix3d Km;
    Km << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1;
    Mat34d P;
    P.leftCols<3>() = Km;
    P.col(3) = Km * t;
    return P;
}

Isometry3d interpolatePose(const Isometry3d& a, const Isometry3d& b, double t) {
    Isometry3d out = Isometry3d::Identity();
    const Eigen::Quaterniond qa(a.rotation()), qb(b.rotation());
    out.linear() = qa.slerp(t, qb).toRotationMatrix();
    out.translation() = (1 - t) * a.translation() + t * b.translation();
    return out;
}

}  // namespace

CameraIntrinsics kittiLikeIntrinsics() {
    CameraIntrinsics K;
    K.width = 1242;
    K.height = 375;
    K.fx = K.fy = 721.5377;
    K.cx = 609.5593;
    K.cy = 172.854;
    return K;
}

namespace {

constexpr std::size_t kMaxTraffic = 20;

// Phase 1: options that CLI11 cannot check alone; the surround rig.
std::vector<RigCamera> checkOptions(const SimOptions& options) {
    if (options.cameras != 1 && options.cameras != 2) {
        throw ConfigError("vdbmap-sim: --cameras must be 1 or 2, got " +
                          std::to_string(options.cameras));
    }
    const bool surround = options.rig == "surround";
    if (options.rig != "kitti" && !surround) {
        throw ConfigError("vdbmap-sim: --rig must be 'kitti' or 'surround', got '" + options.rig +
                          "'");
    }
    if (surround && options.cameras != 1) {
        throw ConfigError("vdbmap-sim: --cameras " + std::to_string(options.cameras) +
                          " is for the kitti rig; the surround rig has its own four cameras");
    }
    if (options.label_noise_px < 0 || options.label_noise_px > 50) {
        throw ConfigError("vdbmap-sim: --label-noise must be in [0, 50] px, got " +
                          std::to_string(options.label_noise_px));
    }
    if (!(options.lidar_label_flip_rate >= 0.0 && options.lidar_label_flip_rate <= 1.0)) {
        throw ConfigError("vdbmap-sim: --lidar-label-flip must be in [0, 1], got " +
                          std::to_string(options.lidar_label_flip_rate));
    }
    if (options.lidar_label_boundary_px < 0 || options.lidar_label_boundary_px > 50) {
        throw ConfigError("vdbmap-sim: --lidar-label-boundary must be in [0, 50] px, got " +
                          std::to_string(options.lidar_label_boundary_px));
    }
    if (options.traffic > kMaxTraffic) {
        throw ConfigError("vdbmap-sim: --traffic must be in [0, " + std::to_string(kMaxTraffic) +
                          "], got " + std::to_string(options.traffic));
    }
    if (options.traffic > 0 && options.scene != "street") {
        throw ConfigError("vdbmap-sim: --traffic is for the street scene, not '" +
                          options.scene + "'");
    }
    if (!surround) return {};
    try {
        return surroundRig(options.rig_options);
    } catch (const InvalidInput& e) {
        throw ConfigError(std::string("vdbmap-sim: ") + e.what());
    }
}

// Phase 2: the scene and its LiDAR.
struct SceneAndLidar {
    SceneSetup setup;
    LidarModel lidar;
};

SceneAndLidar buildScene(const SimOptions& options) {
    SceneAndLidar out;
    std::string lidar_name = options.lidar;
    if (options.scene == "street") {
        StreetSceneOptions so;
        so.length_m = options.size_m;
        so.frames = options.frames ? options.frames : 20;
        so.seed = options.seed;
        so.spot_dir = options.spot_dir;
        out.setup = buildStreetScene(so);
        if (lidar_name.empty()) lidar_name = "hdl64";
    } else if (options.scene == "suv") {
        SuvSceneOptions so;
        so.frames = options.frames ? options.frames : 126;
        so.seed = options.seed;
        out.setup = buildSuvScene(so);
        if (lidar_name.empty()) lidar_name = "vls128";
    } else {
        throw ConfigError("vdbmap-sim: unknown scene '" + options.scene +
                          "' (valid: street, suv)");
    }
    out.lidar = lidarPreset(lidar_name);
    return out;
}

// Phase 3: the frames. S scene, V vehicle, L LiDAR, C0 camera 0; the world W is C0 at frame 0.
// Moves the scene into W.
struct SimFrames {
    Isometry3d Tr = Isometry3d::Identity();     // T_C0_L
    Isometry3d T_V_L = Isometry3d::Identity();
    Isometry3d T_W_S = Isometry3d::Identity();
    std::vector<Isometry3d> T_W_C0;
    std::size_t size() const { return T_W_C0.size(); }
};

SimFrames placeFrames(SceneSetup& setup) {
    SimFrames frames;
    const std::size_t n_frames = setup.T_S_V.size();
    frames.Tr = simTr();
    frames.T_V_L.translation() = Vec3d(0, 0, setup.lidar_height_m);
    std::vector<Isometry3d> T_S_C0(n_frames);
    for (std::size_t f = 0; f < n_frames; ++f) {
        T_S_C0[f] = setup.T_S_V[f] * frames.T_V_L * frames.Tr.inverse();
    }
    frames.T_W_S = T_S_C0[0].inverse();
    setup.scene.transform(frames.T_W_S);
    frames.T_W_C0.resize(n_frames);
    for (std::size_t f = 0; f < n_frames; ++f) frames.T_W_C0[f] = frames.T_W_S * T_S_C0[f];
    return frames;
}

// Phase 4: calibration, poses, times.
void writeCalibration(const std::filesystem::path& out_dir, const SimFrames& frames,
                      const std::vector<RigCamera>& rig, const std::string& scans_dir,
                      const std::string& labels_dir, double frame_rate_hz) {
    const std::size_t n_frames = frames.size();
    if (!rig.empty()) {
        // Generic layout: the poses are the LiDAR's own, T_W_L = T_W_C0 * Tr.
        std::vector<Isometry3d> T_W_L(n_frames);
        for (std::size_t f = 0; f < n_frames; ++f) T_W_L[f] = frames.T_W_C0[f] * frames.Tr;
        writeKittiPoses(out_dir / "poses.txt", T_W_L);
        writeRigCalibration(out_dir, rig, frames.T_V_L, scans_dir, labels_dir);
    } else {
        KittiCalib calib;
        for (int k = 0; k < 4; ++k) calib.P[k] = projection(kittiLikeIntrinsics(), cameraOffset(k));
        calib.Tr = frames.Tr;
        writeKittiCalib(out_dir / "calib.txt", calib);
        writeKittiPoses(out_dir / "poses.txt", frames.T_W_C0);
    }
    std::ostringstream times;
    times << std::setprecision(9);
    for (std::size_t f = 0; f < n_frames; ++f) times << f / frame_rate_hz << "\n";
    writeText(out_dir / "times.txt", times.str());
}

// The noise-free surface points of all scans, one per 2 cm voxel (gt/observed_points.ply).
class ObservedPoints {
public:
    static constexpr float kVoxelM = 0.02f;
    void add(const std::vector<Vec3f>& points_W) {
        for (const auto& p : points_W) {
            const auto q = (p / kVoxelM).array().floor().cast<std::int64_t>();
            const std::uint64_t key = (static_cast<std::uint64_t>(q.x() & 0x1FFFFF) << 42) |
                                      (static_cast<std::uint64_t>(q.y() & 0x1FFFFF) << 21) |
                                      static_cast<std::uint64_t>(q.z() & 0x1FFFFF);
            if (voxels_.insert(key).second) points_.push_back(p);
        }
    }
    std::vector<Vec3f> take() { return std::move(points_); }

private:
    std::vector<Vec3f> points_;
    std::unordered_set<std::uint64_t> voxels_;
};

// Everything the per-frame phase needs, fixed for the sequence.
struct FrameContext {
    const SimOptions& options;
    const std::filesystem::path& out_dir;
    const SceneSetup& setup;
    const LidarModel& lidar;
    const Raycaster& raycaster;
    const SimFrames& frames;
    const std::vector<RigCamera>& rig;
    std::string scans_dir;
    std::string labels_dir;             // "" = no LiDAR labels
    std::vector<std::uint8_t> scene_classes;
    ImagingOptions imaging;
    const TrafficFrames* traffic = nullptr;  // null = no --traffic
};

// The geometry of one frame: the static scene, or the static scene with the traffic.
struct FrameScene {
    const SimScene* scene = nullptr;
    const Raycaster* raycaster = nullptr;
    const TrafficFrame* traffic = nullptr;  // null = no movers
};

// Phase 5a: the scan of frame f and its labels.
void writeFrameScan(const FrameContext& c, const FrameScene& fs, std::size_t f,
                    std::uint64_t frame_seed, SimSummary& summary, ObservedPoints& observed) {
    const Isometry3d T_W_L = c.frames.T_W_C0[f] * c.frames.Tr;
    const LidarScan scan = simulateScan(c.lidar, *fs.raycaster, T_W_L, frame_seed);
    writeBin(c.out_dir / c.scans_dir / (frameName(f) + ".bin"), scan.points_L);
    summary.points += scan.points_L.size();
    if (fs.traffic) {
        // gt/observed_points.ply is the static world: the movers' points stay out.
        std::vector<Vec3f> static_points;
        for (std::size_t i = 0; i < scan.faces.size(); ++i) {
            if (fs.traffic->instanceOf(scan.faces[i]) == 0) {
                static_points.push_back(scan.true_points_W[i]);
            }
        }
        observed.add(static_points);
    } else {
        observed.add(scan.true_points_W);
    }
    if (c.labels_dir.empty()) return;
    SimLidarLabelOptions lo;
    lo.semantickitti_ids = c.options.lidar_label_semantickitti_ids;
    lo.flip_rate = c.options.lidar_label_flip_rate;
    lo.boundary_px = c.options.lidar_label_boundary_px;
    std::mt19937_64 rng(frame_seed ^ 0x1abe15ULL);
    LidarLabels labels =
        simulateLidarLabels(scan, c.lidar, fs.scene->face_labels, c.scene_classes, lo, rng);
    if (fs.traffic) {
        markMovingPoints(labels, scan, *fs.traffic, c.traffic->movers(), lo.semantickitti_ids);
    }
    writeLidarLabels(c.out_dir / c.labels_dir / (frameName(f) + ".label"), labels);
}

// The pixels of a rendered view that show a mover (--traffic) or an occluder box (--occluders,
// layer 1): 255 there, 0 elsewhere. Ground truth for texture.mrf's image_masks.
cv::Mat moverMask(const RenderedView& view, const TrafficFrame* traffic) {
    cv::Mat mask(view.layer.size(), CV_8UC1, cv::Scalar(0));
    for (int y = 0; y < mask.rows; ++y) {
        for (int x = 0; x < mask.cols; ++x) {
            const std::uint8_t layer = view.layer.at<std::uint8_t>(y, x);
            const int face = view.face.at<std::int32_t>(y, x);
            const bool mover = layer == 0 && traffic && face >= 0 &&
                               static_cast<std::size_t>(face) >= traffic->static_faces;
            if (mover || layer == 1) mask.at<std::uint8_t>(y, x) = 255;
        }
    }
    return mask;
}

// Phase 5b: the colour and semantic images of frame f (returns its exposure).
double writeFrameImages(const FrameContext& c, const FrameScene& fs, std::size_t f,
                        std::uint64_t frame_seed, std::vector<std::size_t>& occluder_frames) {
    const SimScene& scene = *fs.scene;
    std::mt19937_64 rng(frame_seed ^ 0x5eedULL);
    std::uniform_real_distribution<double> gain(1.0 - c.options.exposure_spread,
                                                1.0 + c.options.exposure_spread);
    const double exposure = f == 0 ? 1.0 : gain(rng);
    SimScene occluder;
    std::unique_ptr<Raycaster> occluder_rc;
    if (c.options.occluders && (rng() % 3 == 0)) {
        occluder = makeOccluder(c.frames.T_W_S * c.setup.T_S_V[f], c.setup.occluder_ahead_m, rng,
                                c.options.seed);
        occluder_rc =
            std::make_unique<Raycaster>(occluder.mesh.positions, occluder.triangleIndices());
        occluder_frames.push_back(f);
    }
    const auto render = [&](const CameraIntrinsics& K_c, const Isometry3d& T_C_W,
                            const std::string& image_folder, const std::string& semantic_folder) {
        std::vector<RenderLayer> layers{
            RenderLayer{&scene.mesh, &scene.textures, fs.raycaster, &scene.face_labels}};
        if (occluder_rc) {
            layers.push_back(RenderLayer{&occluder.mesh, &occluder.textures, occluder_rc.get(),
                                         &occluder.face_labels});
        }
        RenderOptions ro;
        ro.lambert = true;
        RenderedView view = renderView(layers, K_c, T_C_W, ro);
        applyVignettingAndExposure(view.color, c.imaging, exposure);
        addLabelNoise(view.labels, c.imaging, rng);
        writePng(c.out_dir / image_folder / (frameName(f) + ".png"), view.color);
        writePng(c.out_dir / semantic_folder / (frameName(f) + ".png"), view.labels);
        if (fs.traffic || c.options.occluders) {
            writePng(c.out_dir / "gt" / "mover_masks" / image_folder / (frameName(f) + ".png"),
                     moverMask(view, fs.traffic));
        }
    };
    if (!c.rig.empty()) {
        // T_W_V = T_W_C0 * Tr * T_V_L^-1; camera c at T_W_V * T_V_C.
        const Isometry3d T_W_V = c.frames.T_W_C0[f] * c.frames.Tr * c.frames.T_V_L.inverse();
        for (const RigCamera& camera : c.rig) {
            render(camera.intrinsics, (T_W_V * camera.T_V_C).inverse(), "image_" + camera.name,
                   "semantic_" + camera.name);
        }
        return exposure;
    }
    for (int cam = 0; cam < c.options.cameras; ++cam) {
        const int k = 2 + cam;
        Isometry3d T_Ck_C0 = Isometry3d::Identity();
        T_Ck_C0.translation() = cameraOffset(k);
        const std::string kk = std::to_string(k);
        render(kittiLikeIntrinsics(), T_Ck_C0 * c.frames.T_W_C0[f].inverse(), "image_" + kk,
               "semantic_" + kk);
    }
    return exposure;
}

// Phase 6: vignetting.txt and exposure.txt.
void writeImagingFiles(const std::filesystem::path& out_dir, const SimOptions& options,
                       const std::vector<double>& exposure) {
    std::ostringstream vig, exp;
    vig << "# Radial vignetting applied to image_k (paper Sec. vignetting, Rohlfing 2012):\n"
        << "# I_observed = I / g(r), g(r) = 1 + a r^2 + b r^4 + c r^6,\n"
        << "# r = |(u,v) - (cx,cy)| / sqrt(cx^2 + cy^2), (cx,cy) = image centre\n"
        << "# a b c\n"
        << options.vignetting_abc[0] << " " << options.vignetting_abc[1] << " "
        << options.vignetting_abc[2] << "\n";
    writeText(out_dir / "vignetting.txt", vig.str());
    exp << "# per-frame exposure gain multiplied into image_k (frame 0 = 1)\n"
        << std::setprecision(9);
    for (double e : exposure) exp << e << "\n";
    writeText(out_dir / "exposure.txt", exp.str());
}

// Phase 7: gt/mesh.ply with face labels, gt/textured/mesh.obj, gt/observed_points.ply.
void writeGroundTruth(const std::filesystem::path& out_dir, const SimScene& scene,
                      std::vector<Vec3f> observed, SimSummary& summary) {
    TriMesh gt_mesh = scene.toTriMesh();
    gt_mesh.request_face_normals();
    gt_mesh.request_vertex_normals();
    gt_mesh.update_normals();
    const LabelSet label_set = LabelSet::defaults();
    std::vector<std::array<std::uint8_t, 3>> face_colors;
    for (std::uint8_t l : scene.face_labels) face_colors.push_back(label_set.color(l));
    PlyWriteOptions ply;
    ply.face_labels = &scene.face_labels;
    ply.face_colors = &face_colors;
    writeMeshPly(out_dir / "gt" / "mesh.ply", gt_mesh, ply);
    scene.writeTexturedObj(out_dir / "gt" / "textured" / "mesh.obj");
    PointCloud observed_cloud;
    observed_cloud.points = std::move(observed);
    writePlyPoints(out_dir / "gt" / "observed_points.ply", observed_cloud);
    summary.gt_faces = scene.numTriangles();
    summary.observed_points = observed_cloud.size();
}

// Phase 8: held-out views, camera 2 halfway between frames, no vignetting, no exposure change.
void writeHeldOutViews(const std::filesystem::path& out_dir, const SimOptions& options,
                       const SimScene& scene, const Raycaster& raycaster,
                       const SimFrames& frames) {
    const CameraIntrinsics K = kittiLikeIntrinsics();
    const std::size_t n_frames = frames.size();
    std::vector<GtView> views;
    const std::size_t n_views = std::min(options.gt_views, n_frames > 1 ? n_frames - 1 : 0);
    for (std::size_t v = 0; v < n_views; ++v) {
        const std::size_t f = (v * (n_frames - 1)) / n_views;
        const Isometry3d T_W_C0_mid =
            interpolatePose(frames.T_W_C0[f], frames.T_W_C0[f + 1], 0.5);
        Isometry3d T_C2_C0 = Isometry3d::Identity();
        T_C2_C0.translation() = cameraOffset(2);
        GtView view;
        view.image = "view_" + frameName(v) + ".png";
        view.intrinsics = K;
        view.T_W_C = T_W_C0_mid * T_C2_C0.inverse();
        RenderOptions ro;
        ro.lambert = true;
        const RenderedView r = renderView(
            {RenderLayer{&scene.mesh, &scene.textures, &raycaster, &scene.face_labels}}, K,
            view.T_W_C.inverse(), ro);
        writePng(out_dir / "gt" / "views" / view.image, r.color);
        views.push_back(view);
    }
    writeGtViews(out_dir / "gt" / "views", views);
}

// Phase 9: gt/sim.json, what was simulated.
void writeSimInfo(const std::filesystem::path& out_dir, const SimOptions& options,
                  const std::vector<RigCamera>& rig, const LidarModel& lidar,
                  const std::vector<std::size_t>& occluder_frames, const SimSummary& summary) {
    nlohmann::json info;
    info["scene"] = options.scene;
    info["seed"] = options.seed;
    info["frames"] = summary.frames;
    info["lidar"] = lidar.name;
    info["size_m"] = options.size_m;
    info["rig"] = options.rig;
    if (!rig.empty()) {
        info["cameras"] = nlohmann::json::array();
        for (const RigCamera& camera : rig) info["cameras"].push_back(camera.name);
        info["rig_image_px"] = {options.rig_options.width_px, options.rig_options.height_px};
        info["rig_hfov_deg"] = options.rig_options.hfov_deg;
    } else {
        info["cameras"] = options.cameras;
    }
    info["occluders"] = options.occluders;
    info["label_noise_px"] = options.label_noise_px;
    info["lidar_labels"] = options.lidar_labels;
    if (options.lidar_labels) {
        info["lidar_label_ids"] = options.lidar_label_semantickitti_ids ? "semantickitti" : "ours";
        info["lidar_label_flip_rate"] = options.lidar_label_flip_rate;
        info["lidar_label_boundary_px"] = options.lidar_label_boundary_px;
    }
    info["occluder_frames"] = occluder_frames;
    if (options.traffic > 0) info["traffic"] = options.traffic;  // cars; gt/movers.json  // frames whose images show a pedestrian box
    info["vignetting_abc"] = options.vignetting_abc;
    info["lidar_points"] = summary.points;
    info["gt_faces"] = summary.gt_faces;
    info["observed_points"] = summary.observed_points;
    info["observed_voxel_m"] = ObservedPoints::kVoxelM;
    writeText(out_dir / "gt" / "sim.json", info.dump(2) + "\n");
}

// Phase 2b (--traffic): the movers, laid out in the scene frame S (before placeFrames moves
// the scene), their poses then moved into W.
std::vector<Mover> buildTraffic(const SimOptions& options, const SceneSetup& setup_S) {
    if (options.traffic == 0) return {};
    const Raycaster static_S(setup_S.scene.mesh.positions, setup_S.scene.triangleIndices());
    return buildStreetTraffic(setup_S, static_S, options.traffic, options.seed);
}

// Phase 10 (--traffic): gt/movers.json.
void writeMovers(const std::filesystem::path& out_dir, const TrafficFrames& traffic,
                 const SceneSetup& setup) {
    MoversFile file;
    for (std::size_t f = 0; f < setup.T_S_V.size(); ++f) {
        file.times_s.push_back(static_cast<double>(f) / setup.frame_rate_hz);
    }
    file.movers = traffic.movers();
    writeMoversJson(out_dir / "gt" / "movers.json", file);
}

}  // namespace

SimSummary writeSimSequence(const SimOptions& options, const std::filesystem::path& out_dir) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<RigCamera> rig = checkOptions(options);
    SceneAndLidar built = buildScene(options);
    SceneSetup& setup = built.setup;
    std::vector<Mover> movers = buildTraffic(options, setup);
    const SimFrames frames = placeFrames(setup);
    for (Mover& m : movers) {
        for (Isometry3d& T : m.T_W_O) T = frames.T_W_S * T;
    }
    const TrafficFrames traffic(std::move(movers), options.seed);
    const std::size_t n_frames = frames.size();
    const SimScene& scene = setup.scene;
    const Raycaster raycaster(scene.mesh.positions, scene.triangleIndices());
    logInfo("vdbmap-sim: scene '" + options.scene + "' with " +
            std::to_string(scene.numTriangles()) + " triangles, " + std::to_string(n_frames) +
            " frames, LiDAR " + built.lidar.name);

    FrameContext context{options, out_dir, setup, built.lidar, raycaster, frames, rig,
                         rig.empty() ? "velodyne" : "scans",
                         options.lidar_labels ? "labels" : "", {}, {}};
    const std::set<std::uint8_t> classes(scene.face_labels.begin(), scene.face_labels.end());
    context.scene_classes.assign(classes.begin(), classes.end());
    context.imaging.vignetting_abc = options.vignetting_abc;
    context.imaging.label_noise_px = options.label_noise_px;
    if (!traffic.movers().empty()) {
        context.traffic = &traffic;
        for (const Mover& m : traffic.movers()) context.scene_classes.push_back(m.class_id);
        std::sort(context.scene_classes.begin(), context.scene_classes.end());
        context.scene_classes.erase(
            std::unique(context.scene_classes.begin(), context.scene_classes.end()),
            context.scene_classes.end());
    }
    std::filesystem::create_directories(out_dir / context.scans_dir);
    if (options.lidar_labels) std::filesystem::create_directories(out_dir / context.labels_dir);
    std::filesystem::create_directories(out_dir / "gt" / "views");
    std::filesystem::create_directories(out_dir / "gt" / "textured");
    writeCalibration(out_dir, frames, rig, context.scans_dir, context.labels_dir,
                     setup.frame_rate_hz);

    SimSummary summary;
    summary.frames = n_frames;
    ObservedPoints observed;
    std::vector<double> exposure(n_frames, 1.0);
    std::vector<std::size_t> occluder_frames;
    {
        Progress progress("vdbmap-sim " + options.scene, n_frames, options.quiet);
        for (std::size_t f = 0; f < n_frames; ++f) {
            const std::uint64_t frame_seed = options.seed * 1000003ULL + f * 7919ULL + 17ULL;
            std::optional<TrafficFrame> moving;
            if (context.traffic) moving = context.traffic->frame(scene, f);
            const FrameScene fs = moving ? FrameScene{&moving->scene, moving->raycaster.get(),
                                                      &*moving}
                                         : FrameScene{&scene, &raycaster, nullptr};
            writeFrameScan(context, fs, f, frame_seed, summary, observed);
            if (options.images) {
                exposure[f] = writeFrameImages(context, fs, f, frame_seed, occluder_frames);
            }
            progress.tick();
        }
    }
    if (options.images) writeImagingFiles(out_dir, options, exposure);
    writeGroundTruth(out_dir, scene, observed.take(), summary);
    writeHeldOutViews(out_dir, options, scene, raycaster, frames);
    summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    writeSimInfo(out_dir, options, rig, built.lidar, occluder_frames, summary);
    if (context.traffic) writeMovers(out_dir, traffic, setup);
    return summary;
}

}  // namespace vdbmap
