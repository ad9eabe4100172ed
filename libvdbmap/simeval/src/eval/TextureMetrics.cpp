// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/eval/TextureMetrics.h"

#include <cmath>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/TexturedRender.h"

namespace vdbmap {

void accumulateImageError(const cv::Mat& rendered_bgr, const cv::Mat& rendered_mask,
                          const cv::Mat& gt_bgr, const cv::Mat& gt_surface,
                          TextureMetrics& metrics, double& sum_abs, double& sum_sq,
                          std::size_t& gt_pixels) {
    if (rendered_bgr.size() != gt_bgr.size() || rendered_bgr.type() != CV_8UC3 ||
        gt_bgr.type() != CV_8UC3) {
        throw InvalidInput("texture evaluation: rendered image " +
                           std::to_string(rendered_bgr.cols) + "x" +
                           std::to_string(rendered_bgr.rows) + " and ground-truth image " +
                           std::to_string(gt_bgr.cols) + "x" + std::to_string(gt_bgr.rows) +
                           " differ in size or are not 8-bit colour");
    }
    for (int y = 0; y < gt_bgr.rows; ++y) {
        for (int x = 0; x < gt_bgr.cols; ++x) {
            const bool gt_has = gt_surface.empty() || gt_surface.at<std::uint8_t>(y, x) != 0;
            if (!gt_has) continue;
            ++gt_pixels;
            if (!rendered_mask.empty() && rendered_mask.at<std::uint8_t>(y, x) == 0) continue;
            const auto& a = rendered_bgr.at<cv::Vec3b>(y, x);
            const auto& b = gt_bgr.at<cv::Vec3b>(y, x);
            for (int c = 0; c < 3; ++c) {
                const double d = static_cast<double>(a[c]) - static_cast<double>(b[c]);
                sum_abs += std::abs(d);
                sum_sq += d * d;
            }
            ++metrics.pixels_compared;
        }
    }
}

void finishTextureMetrics(TextureMetrics& m, double sum_abs, double sum_sq,
                          std::size_t gt_pixels) {
    if (m.pixels_compared == 0) return;
    const double n = 3.0 * static_cast<double>(m.pixels_compared);
    m.mae = sum_abs / n;
    const double mse = sum_sq / n;
    m.psnr_db = mse > 0 ? std::min(TextureMetrics::kMaxPsnrDb, 10.0 * std::log10(255.0 * 255.0 / mse))
                        : TextureMetrics::kMaxPsnrDb;
    m.coverage = gt_pixels ? static_cast<double>(m.pixels_compared) / gt_pixels : 0.0;
}

TextureMetrics evaluateTexture(const ObjMesh& pred, const std::vector<cv::Mat>& pred_textures,
                               const std::vector<GtView>& views,
                               const std::vector<cv::Mat>& gt_images, const Raycaster* gt,
                               std::vector<cv::Mat>* renders) {
    if (views.size() != gt_images.size()) {
        throw InvalidInput("evaluateTexture: " + std::to_string(views.size()) + " views but " +
                           std::to_string(gt_images.size()) + " images");
    }
    std::vector<std::array<std::uint32_t, 3>> tris;
    tris.reserve(pred.triangles.size());
    for (const auto& t : pred.triangles) tris.push_back(t.v);
    const Raycaster pred_rc(pred.positions, tris);
    TextureMetrics m;
    double sum_abs = 0, sum_sq = 0;
    std::size_t gt_pixels = 0;
    for (std::size_t i = 0; i < views.size(); ++i) {
        const Isometry3d T_C_W = views[i].T_W_C.inverse();
        const RenderedView r =
            renderView({RenderLayer{&pred, &pred_textures, &pred_rc, nullptr}},
                       views[i].intrinsics, T_C_W, RenderOptions{});
        cv::Mat rendered_mask = r.face >= 0;
        cv::Mat gt_surface;
        if (gt) {
            // Only the hit mask of the ground truth is needed: render depth with a bare layer.
            ObjMesh gt_obj;
            gt_obj.materials.push_back(ObjMaterial{});
            std::vector<cv::Mat> gt_tex{cv::Mat(1, 1, CV_8UC3, cv::Scalar(0, 0, 0))};
            gt_obj.triangles.resize(gt->numTriangles());
            const RenderedView g = renderView({RenderLayer{&gt_obj, &gt_tex, gt, nullptr}},
                                              views[i].intrinsics, T_C_W, RenderOptions{});
            gt_surface = g.face >= 0;
        } else {
            cv::Mat channels[3];
            cv::split(gt_images[i], channels);
            gt_surface = (channels[0] > 0) | (channels[1] > 0) | (channels[2] > 0);
        }
        TextureMetrics view;
        double view_abs = 0, view_sq = 0;
        std::size_t view_gt_pixels = 0;
        accumulateImageError(r.color, rendered_mask, gt_images[i], gt_surface, view, view_abs,
                             view_sq, view_gt_pixels);
        m.pixels_compared += view.pixels_compared;
        sum_abs += view_abs;
        sum_sq += view_sq;
        gt_pixels += view_gt_pixels;
        finishTextureMetrics(view, view_abs, view_sq, view_gt_pixels);
        m.view_psnr_db.push_back(view.psnr_db);
        if (renders) {
            cv::Mat shown(r.color.size(), CV_8UC3, cv::Scalar(0, 0, 0));
            r.color.copyTo(shown, rendered_mask);
            renders->push_back(shown);
        }
        ++m.views;
    }
    finishTextureMetrics(m, sum_abs, sum_sq, gt_pixels);
    return m;
}

}  // namespace vdbmap
