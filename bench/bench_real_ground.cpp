// SPDX-License-Identifier: Apache-2.0
// Issue 16's real-data check on every real KITTI scan given, not only the one the test keeps
// (tests/unit/RealGroundPatchTest.cpp, frame 000000). Each scan is integrated alone in its own
// frame at 0.1 m; its ground patch (tests/support/RealGroundPatch.h: the flat, level road 4 to
// 20 m around the car) scores the meshes of fixed eps_min, fixed eps_max and the adaptive mode
// with each merge_points setting: the share of ground cells left empty, and the mean vertex
// distance to the cells' planes on the cells both it and fixed eps_max cover.
//
//   build/bin/bench_real_ground --range 0.1 0.3 tests/data/kitti_scans_real/*.bin
//
// Prints a Markdown table (one row per scan and mode, then the mean over the scans) on stdout.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "support/RealGroundPatch.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/PointCloudIO.h"

using namespace vdbmap;
using namespace vdbmap::test;

namespace {

struct Variant {
    const char* name;
    TruncationMode mode;
    int merge_divisions;
};

/// Per variant, summed over the scans: holes, its error and fixed eps_max's on their common
/// cells, and the scans where it is no less accurate than fixed eps_max.
struct Tally {
    double holes = 0.0, error_m = 0.0, fixed_error_m = 0.0;
    int held = 0;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vdbmap: the real ground patch of each KITTI scan, adaptive against fixed eps"};
    std::vector<double> range_m{0.1, 0.3};
    std::vector<std::string> scans;
    app.add_option("--range", range_m, "eps_min eps_max (m)")->expected(2)->allow_extra_args(false);
    app.add_option("scans", scans, "KITTI .bin scans (HDL-64E, sensor frame)")->required();
    CLI11_PARSE(app, argc, argv);
    const double lo = range_m[0], hi = range_m[1];
    if (!(lo > 0.0 && lo <= hi)) {
        std::fprintf(stderr, "bench_real_ground: --range needs 0 < eps_min <= eps_max, got %g %g\n", lo, hi);
        return 2;
    }

    const std::vector<Variant> variants = {{"adaptive, merge_points none", TruncationMode::Adaptive, 0},
                                           {"adaptive, merge_points voxel", TruncationMode::Adaptive, 1},
                                           {"adaptive, merge_points half_voxel", TruncationMode::Adaptive, 2}};
    std::vector<Tally> tally(variants.size());
    double small_holes = 0.0, large_holes = 0.0;
    std::printf("range [%.2f, %.2f] m, voxel 0.1 m; error in mm on the cells both the mode and "
                "fixed %.2f cover\n\n",
                lo, hi, hi);
    std::printf("| scan | mode | holes | error (fixed %.2f) [mm] | no less accurate |\n", hi);
    std::printf("|---|---|---|---|---|\n");
    try {
        for (const std::string& path : scans) {
            const std::vector<Vec3f> scan = readBin(path).points;
            const auto patch = groundPatch(scan);
            const std::string name = std::filesystem::path(path).stem().string();
            const PatchScore small = scoreGroundPatch(TruncationMode::Fixed, lo, lo, scan, patch);
            const PatchScore large = scoreGroundPatch(TruncationMode::Fixed, hi, hi, scan, patch);
            small_holes += small.holes;
            large_holes += large.holes;
            std::printf("| %s | fixed %.2f / %.2f (%zu cells) | %.3f / %.3f | | |\n", name.c_str(),
                        lo, hi, patch.size(), small.holes, large.holes);
            for (std::size_t v = 0; v < variants.size(); ++v) {
                const PatchScore s = scoreGroundPatch(variants[v].mode, lo, hi, scan, patch,
                                                      variants[v].merge_divisions);
                const auto [err, fixed_err] = commonError(s, large);
                const bool held = err <= fixed_err;
                tally[v].holes += s.holes;
                tally[v].error_m += err;
                tally[v].fixed_error_m += fixed_err;
                tally[v].held += held ? 1 : 0;
                std::printf("| %s | %s | %.3f | %.3f (%.3f) | %s |\n", name.c_str(), variants[v].name,
                            s.holes, 1e3 * err, 1e3 * fixed_err, held ? "yes" : "**no**");
            }
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "bench_real_ground: %s\n", e.what());
        return 1;
    }
    const double n = static_cast<double>(scans.size());
    std::printf("\nMean over %zu scans (fixed %.2f leaves %.3f of the cells empty, fixed %.2f "
                "%.3f):\n\n",
                scans.size(), lo, small_holes / n, hi, large_holes / n);
    std::printf("| mode | holes | error (fixed %.2f) [mm] | scans no less accurate |\n", hi);
    std::printf("|---|---|---|---|\n");
    for (std::size_t v = 0; v < variants.size(); ++v)
        std::printf("| %s | %.3f | %.3f (%.3f) | %d of %zu |\n", variants[v].name, tally[v].holes / n,
                    1e3 * tally[v].error_m / n, 1e3 * tally[v].fixed_error_m / n, tally[v].held,
                    scans.size());
    return 0;
}
