// SPDX-License-Identifier: Apache-2.0
// texture_render_views GT_DIR OUT_DIR RUN_DIR... [--crop K X Y W H]
// Renders each run's textured mesh (RUN_DIR/textured/mesh.obj) from the held-out views of a
// simulated sequence (GT_DIR/views/), without shading, as `vdbmap eval` does to score it, and
// writes OUT_DIR/view_<k>_<run index>.png and gt_<k>.png (the held-out image). With --crop, also
// OUT_DIR/crop_<K>.jpg: the rectangle (X, Y, W, H) of view K from every run, left to right,
// then the held-out image, each scaled 2x. For the before/after pictures of docs/texturing.md.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "vdbmap/eval/GtViews.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/TexturedRender.h"
#include "vdbmap/sim/SimScene.h"

namespace fs = std::filesystem;

namespace {

std::vector<cv::Mat> renderRun(const fs::path& run_dir, const std::vector<vdbmap::GtView>& views) {
    vdbmap::ObjMesh obj;
    std::vector<cv::Mat> textures;
    vdbmap::loadTexturedObj(run_dir / "textured" / "mesh.obj", obj, textures);
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (const auto& tri : obj.triangles) triangles.push_back(tri.v);
    const vdbmap::Raycaster raycaster(obj.positions, triangles);
    std::vector<cv::Mat> images;
    for (const auto& view : views) {
        images.push_back(
            vdbmap::renderView({vdbmap::RenderLayer{&obj, &textures, &raycaster, nullptr}},
                               view.intrinsics, view.T_W_C.inverse())
                .color);
    }
    return images;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    std::vector<int> crop;
    for (std::size_t i = 0; i < args.size(); ++i) {
        if (args[i] == "--crop" && i + 5 < args.size()) {
            for (int k = 1; k <= 5; ++k) crop.push_back(std::stoi(args[i + k]));
            args.erase(args.begin() + static_cast<long>(i), args.begin() + static_cast<long>(i) + 6);
            break;
        }
    }
    if (args.size() < 3) {
        std::cerr << "usage: texture_render_views GT_DIR OUT_DIR RUN_DIR... [--crop K X Y W H]\n";
        return 2;
    }
    try {
        const fs::path gt_dir = args[0], out_dir = args[1];
        fs::create_directories(out_dir);
        const auto views = vdbmap::readGtViews(gt_dir / "views");
        std::vector<cv::Mat> gt;
        for (std::size_t k = 0; k < views.size(); ++k) {
            gt.push_back(vdbmap::readColorImage(gt_dir / "views" / views[k].image));
            cv::imwrite((out_dir / ("gt_" + std::to_string(k) + ".png")).string(), gt[k]);
        }
        std::vector<std::vector<cv::Mat>> runs;
        for (std::size_t r = 2; r < args.size(); ++r) {
            runs.push_back(renderRun(args[r], views));
            for (std::size_t k = 0; k < views.size(); ++k) {
                cv::imwrite((out_dir / ("view_" + std::to_string(k) + "_" +
                                        std::to_string(r - 2) + ".png"))
                                .string(),
                            runs.back()[k]);
            }
        }
        if (crop.size() == 5) {
            const auto k = static_cast<std::size_t>(crop[0]);
            const cv::Rect rect(crop[1], crop[2], crop[3], crop[4]);
            std::vector<cv::Mat> tiles;
            for (const auto& run : runs) {
                cv::Mat big;
                cv::resize(run.at(k)(rect), big, {}, 2.0, 2.0, cv::INTER_NEAREST);
                tiles.push_back(big);
                tiles.push_back(cv::Mat(big.rows, 6, CV_8UC3, cv::Scalar(255, 255, 255)));
            }
            cv::Mat big;
            cv::resize(gt.at(k)(rect), big, {}, 2.0, 2.0, cv::INTER_NEAREST);
            tiles.push_back(big);
            cv::Mat row;
            cv::hconcat(tiles, row);
            cv::imwrite((out_dir / ("crop_" + std::to_string(k) + ".jpg")).string(), row);
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "texture_render_views: " << e.what() << "\n";
        return 1;
    }
}
