// SPDX-License-Identifier: Apache-2.0
// vdbmap-sim: writes a simulated sensor sequence with ground truth in the KITTI layout (or,
// with --rig surround, the generic layout with four cameras and its dataset.yaml).
#include <tbb/global_control.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <thread>

#include "StagedDir.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/sim/SimLayout.h"
#include "vdbmap/sim/SimSequence.h"

namespace fs = std::filesystem;

namespace {

fs::path executableDir() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : exe.parent_path();
}

// The Spot mesh ships in tests/data/meshes (source tree) and share/vdbmap/meshes (install).
std::optional<fs::path> findSpotDir(const std::string& assets) {
    std::vector<fs::path> candidates;
    if (!assets.empty()) candidates.emplace_back(assets);
    if (const char* env = std::getenv("VDBMAP_DATA_DIR")) {
        candidates.emplace_back(fs::path(env) / "meshes");
    }
    const fs::path exe_dir = executableDir();
    if (!exe_dir.empty()) {
        candidates.push_back(exe_dir / ".." / "share" / "vdbmap" / "meshes");
        candidates.push_back(exe_dir / ".." / ".." / "tests" / "data" / "meshes");
        candidates.push_back(exe_dir / ".." / "tests" / "data" / "meshes");
    }
    for (const auto& c : candidates) {
        if (fs::exists(c / "spot_triangulated.obj") && fs::exists(c / "spot_texture.png")) {
            return fs::weakly_canonical(c);
        }
    }
    return std::nullopt;
}

// The command-line values that are not SimOptions fields.
struct CliExtras {
    std::string out_dir;
    std::string assets;
    int threads = 0;
    bool no_lidar_labels = false;
    std::string lidar_label_ids = "semantickitti";
    bool no_images = false;
    vdbmap::SimLayoutOptions layout;  // --layout, --sequence
};

void addOptions(CLI::App& app, vdbmap::SimOptions& options, CliExtras& cli) {
    app.add_option("scene", options.scene, "Scene: street or suv")
        ->required()
        ->check(CLI::IsMember({"street", "suv"}));
    app.add_option("-o,--output", cli.out_dir, "Output folder (the sequence)")->required();
    app.add_option("--frames", options.frames,
                   "Number of frames (default: street 20, suv 126 = one lap)");
    app.add_option("--seed", options.seed, "Random seed (output is deterministic for a seed)");
    app.add_option("--lidar", options.lidar, "LiDAR preset: hdl64 or vls128 (default per scene)")
        ->check(CLI::IsMember({"hdl64", "vls128"}));
    app.add_option("--size", options.size_m, "Street length in metres (>= 20)");
    app.add_option("--cameras", options.cameras, "kitti rig: 1 (image_2) or 2 (image_2 + image_3)")
        ->check(CLI::Range(1, 2));
    app.add_option("--rig", options.rig,
                   "kitti: KITTI layout, forward camera(s) (default); surround: generic layout "
                   "with front, left, rear and right cameras and a dataset.yaml")
        ->check(CLI::IsMember({"kitti", "surround"}));
    app.add_option("--rig-width", options.rig_options.width_px, "surround rig: image width, px")
        ->check(CLI::Range(16, 8192));
    app.add_option("--rig-height", options.rig_options.height_px, "surround rig: image height, px")
        ->check(CLI::Range(16, 8192));
    app.add_option("--rig-hfov-deg", options.rig_options.hfov_deg,
                   "surround rig: horizontal field of view of each camera, deg")
        ->check(CLI::Range(10.0, 170.0));
    app.add_flag("--occluders", options.occluders,
                 "Moving pedestrian boxes in some frames (images only)");
    app.add_option("--traffic", options.traffic,
                   "Street traffic: N cars (one creeping ahead in the ego lane, the others "
                   "oncoming), a van crossing and three pedestrians, in the LiDAR and the "
                   "images; gt/movers.json has their poses (default 0: none)")
        ->check(CLI::Range(0, 20));
    app.add_option("--label-noise", options.label_noise_px,
                   "Jitter of semantic class boundaries in pixels")
        ->check(CLI::Range(0, 50));
    app.add_flag("--no-lidar-labels", cli.no_lidar_labels,
                 "Do not write per-point LiDAR labels (labels/NNNNNN.label)");
    app.add_option("--lidar-label-ids", cli.lidar_label_ids,
                   "Ids in the .label files: semantickitti (raw SemanticKITTI ids, map them "
                   "with config/label_maps/semantickitti.txt) or ours (the label set's ids)")
        ->check(CLI::IsMember({"semantickitti", "ours"}));
    app.add_option("--lidar-label-flip", options.lidar_label_flip_rate,
                   "Probability that a LiDAR point's label is flipped to another scene class")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--lidar-label-boundary", options.lidar_label_boundary_px,
                   "Jitter of LiDAR label class boundaries in range-image pixels")
        ->check(CLI::Range(0, 50));
    app.add_flag("--no-images", cli.no_images, "Write LiDAR and ground truth only");
    app.add_option("--layout", cli.layout.layout,
                   "Folder layout (docs/DATA.md): sequence (default), kitti-odometry, "
                   "semantic-kitti or kitti360, as those datasets are downloaded")
        ->check(CLI::IsMember(vdbmap::simLayoutNames()));
    app.add_option("--sequence", cli.layout.sequence,
                   "Sequence number of the KITTI layouts (default 00) or the KITTI-360 drive "
                   "(default 2013_05_28_drive_0000_sync)");
    app.add_option("--gt-views", options.gt_views, "Held-out ground-truth views (gt/views)");
    app.add_option("--assets", cli.assets,
                   "Folder with spot_triangulated.obj + spot_texture.png (default: search "
                   "$VDBMAP_DATA_DIR/meshes, <prefix>/share/vdbmap/meshes, tests/data/meshes)");
    app.add_option("--threads", cli.threads, "Worker threads (0 = all cores)");
    app.add_flag("-q,--quiet", options.quiet, "No progress and no info messages");
}

// The street's Spot mesh: --assets, else found, else a warning (no class-20 object).
void findAssets(vdbmap::SimOptions& options, const std::string& assets) {
    if (options.scene != "street") return;
    if (const auto spot = findSpotDir(assets)) {
        options.spot_dir = *spot;
    } else if (!assets.empty()) {
        throw vdbmap::IoError("--assets " + assets +
                              ": no spot_triangulated.obj + spot_texture.png there");
    } else {
        vdbmap::logWarn("vdbmap-sim: Spot mesh not found (use --assets DIR); the street "
                        "has no class-20 object");
    }
}

// Writes the sequence; it appears whole or not at all (a failed or killed run leaves nothing).
void simulate(vdbmap::SimOptions& options, const CliExtras& cli) {
    findAssets(options, cli.assets);
    vdbmap::sim::StagedDir staged(cli.out_dir);
    const vdbmap::SimSummary s = vdbmap::writeSimLayout(options, cli.layout, staged.path());
    staged.commit();
    if (!options.quiet) {
        std::cout << "wrote " << cli.out_dir << ": " << s.frames << " frames, " << s.points
                  << " LiDAR points, " << s.gt_faces << " ground-truth faces, "
                  << s.observed_points << " observed points, " << s.seconds << " s\n";
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "vdbmap-sim: simulated LiDAR + camera sequences with ground truth (KITTI layout, or "
        "the generic layout with --rig surround)"};
    vdbmap::SimOptions options;
    CliExtras cli;
    addOptions(app, options, cli);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help prints and exits 0; a bad command line is a usage error, exit 2 (like vdbmap).
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    options.images = !cli.no_images;
    options.lidar_labels = !cli.no_lidar_labels;
    options.lidar_label_semantickitti_ids = cli.lidar_label_ids == "semantickitti";
    if (options.quiet) vdbmap::setLogLevel(vdbmap::LogLevel::Warn);
    const std::size_t n_threads =
        cli.threads > 0 ? static_cast<std::size_t>(cli.threads)
                        : std::max(1u, std::thread::hardware_concurrency());
    tbb::global_control control(tbb::global_control::max_allowed_parallelism, n_threads);
    try {
        simulate(options, cli);
    } catch (const vdbmap::ConfigError& e) {
        std::cerr << "vdbmap-sim: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "vdbmap-sim: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
