// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/render/TexturedRender.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "vdbmap/Error.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

namespace {

int wrapIndex(int i, int n) {
    const int r = i % n;
    return r < 0 ? r + n : r;
}

}  // namespace

Vec3f sampleTexture(const cv::Mat& texture_bgr, float u, float v) {
    const int w = texture_bgr.cols;
    const int h = texture_bgr.rows;
    if (!std::isfinite(u) || !std::isfinite(v)) u = v = 0.0f;
    // OBJ: v up; pixel centres at (i + 0.5) / size.
    const float x = (u - std::floor(u)) * w - 0.5f;
    const float y = (1.0f - (v - std::floor(v))) * h - 0.5f;
    const int x0 = static_cast<int>(std::floor(x));
    const int y0 = static_cast<int>(std::floor(y));
    const float fx = x - x0;
    const float fy = y - y0;
    auto px = [&](int xi, int yi) {
        const auto& c = texture_bgr.at<cv::Vec3b>(wrapIndex(yi, h), wrapIndex(xi, w));
        return Vec3f(c[0], c[1], c[2]);
    };
    return (1 - fy) * ((1 - fx) * px(x0, y0) + fx * px(x0 + 1, y0)) +
           fy * ((1 - fx) * px(x0, y0 + 1) + fx * px(x0 + 1, y0 + 1));
}

RenderedView renderView(const std::vector<RenderLayer>& layers,
                        const CameraIntrinsics& intrinsics, const Isometry3d& T_C_W,
                        const RenderOptions& options) {
    if (intrinsics.width <= 0 || intrinsics.height <= 0 || !(intrinsics.fx > 0) ||
        !(intrinsics.fy > 0)) {
        throw InvalidInput("renderView: empty camera intrinsics (" +
                           std::to_string(intrinsics.width) + "x" +
                           std::to_string(intrinsics.height) + ")");
    }
    for (const auto& layer : layers) {
        if (!layer.mesh || !layer.textures || !layer.raycaster ||
            layer.textures->size() < layer.mesh->materials.size()) {
            throw InvalidInput("renderView: a layer lacks its mesh, textures or raycaster");
        }
    }
    const int w = intrinsics.width;
    const int h = intrinsics.height;
    RenderedView out;
    out.color = cv::Mat(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
    out.labels = cv::Mat(h, w, CV_8UC1, cv::Scalar(255));
    out.depth = cv::Mat(h, w, CV_32FC1, cv::Scalar(0));
    out.layer = cv::Mat(h, w, CV_8UC1, cv::Scalar(255));
    out.face = cv::Mat(h, w, CV_32SC1, cv::Scalar(-1));
    const Isometry3d T_W_C = T_C_W.inverse();
    const Vec3f origin_W = T_W_C.translation().cast<float>();
    const Eigen::Matrix3f R_W_C = T_W_C.rotation().cast<float>();
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
            for (int x = 0; x < w; ++x) {
                const Vec3f dir_C(static_cast<float>((x - intrinsics.cx) / intrinsics.fx),
                                  static_cast<float>((y - intrinsics.cy) / intrinsics.fy), 1.0f);
                const Vec3f dir_W = (R_W_C * dir_C).normalized();
                std::optional<Raycaster::Hit> best;
                std::size_t best_layer = 0;
                for (std::size_t l = 0; l < layers.size(); ++l) {
                    const float t_max = best ? best->distance : options.max_depth_m;
                    auto hit = layers[l].raycaster->intersect(origin_W, dir_W, 0.0f, t_max);
                    if (hit && (!best || hit->distance < best->distance)) {
                        best = hit;
                        best_layer = l;
                    }
                }
                if (!best) continue;
                const RenderLayer& layer = layers[best_layer];
                const ObjMesh::Triangle& tri = layer.mesh->triangles[best->face];
                Vec3f bgr(204, 204, 204);
                if (tri.material < layer.textures->size()) {
                    const cv::Mat& tex = (*layer.textures)[tri.material];
                    if (!layer.mesh->uvs.empty()) {
                        // Embree barycentrics: p = (1-u-v) p0 + u p1 + v p2.
                        const float b1 = best->u, b2 = best->v, b0 = 1.0f - b1 - b2;
                        const Eigen::Vector2f uv = b0 * layer.mesh->uvs[tri.vt[0]] +
                                                   b1 * layer.mesh->uvs[tri.vt[1]] +
                                                   b2 * layer.mesh->uvs[tri.vt[2]];
                        bgr = sampleTexture(tex, uv.x(), uv.y());
                    } else {
                        bgr = sampleTexture(tex, 0.5f, 0.5f);
                    }
                }
                if (options.lambert) {
                    Vec3f n = best->normal_unit;
                    if (n.dot(dir_W) > 0) n = -n;  // two-sided: the side facing the camera
                    const float diffuse = std::max(0.0f, n.dot(options.light_dir_W));
                    bgr *= options.ambient + (1.0f - options.ambient) * diffuse;
                }
                auto& c = out.color.at<cv::Vec3b>(y, x);
                for (int k = 0; k < 3; ++k) {
                    c[k] = static_cast<std::uint8_t>(std::clamp(std::lround(bgr[k]), 0L, 255L));
                }
                out.depth.at<float>(y, x) = best->distance;
                out.face.at<std::int32_t>(y, x) = static_cast<std::int32_t>(best->face);
                out.layer.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(best_layer);
                if (layer.face_labels && best->face < layer.face_labels->size()) {
                    out.labels.at<std::uint8_t>(y, x) = (*layer.face_labels)[best->face];
                }
            }
        }
    });
    return out;
}

}  // namespace vdbmap
