// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "AtlasPacker.h"
#include "Patches.h"
#include "TextureTypes.h"

namespace vdbmap::texture {

/// A rectangle of one view's image copied into the atlas: a whole patch, or one face of a
/// patch too large for a page.
struct Chart {
    std::uint32_t patch = 0;
    std::uint32_t view = 0;
    std::vector<std::uint32_t> faces;
    int x0 = 0, y0 = 0;   ///< top-left source pixel in the view's image (may lie outside it)
    RectSize size;        ///< including the padding border
    RectPlacement place;  ///< in the atlas
};

/// Palette block of the faces no view saw: cells of one colour, kFillCellPx square, in rows of
/// kFillColumns.
inline constexpr int kFillCellPx = 4;
inline constexpr int kFillColumns = 64;

/// Where every face's texture lives.
struct AtlasLayout {
    std::vector<Chart> charts;
    std::vector<RectSize> pages;
    std::vector<std::uint32_t> face_chart;  ///< per face; kNoLabel = untextured (fill block)
    bool has_fill_block = false;
    RectPlacement fill_place;  ///< the palette block for faces no view saw
    RectSize fill_size;        ///< kFillColumns cells per row, kFillCellPx square cells
    int fill_cells = 0;
};

/// Lays out the patches: each becomes one chart, the bounding box of its faces' projections
/// (`face_pixels[f]`, in the face's chosen view) grown by `padding_px` on every side (real
/// image pixels around the faces, against bleeding under bilinear lookup and mip-mapping).
/// A patch wider or taller than `max_size_px` is split into one chart per face. If any face
/// has no patch, a palette block of `fill_cells` (>= 1) colour cells is added. Then all charts
/// are packed (packRects).
AtlasLayout layoutAtlas(const std::vector<Patch>& patches,
                        const std::vector<std::array<Eigen::Vector2f, 3>>& face_pixels,
                        std::size_t num_faces, int padding_px, int max_size_px, int fill_cells = 1);

/// Copies the chart's source rectangle of `image_f32` (CV_32FC3, coordinates clamped to the
/// image) into `page` (CV_8UC3) at its placement, rounding and saturating. `image_f32` may be a
/// crop whose top-left pixel is `origin` of an image of `image_size` (default: the whole image)
/// that holds the clamped rectangle.
void cutChart(const cv::Mat& image_f32, const Chart& chart, cv::Mat& page,
              cv::Point origin = {0, 0}, cv::Size image_size = {});

/// Adds the global colour adjustment to a chart already in `page`: inside each face the
/// correction is interpolated barycentrically from its corners (paper Sec. 5.2.3); padding
/// pixels take the correction of the nearest face pixel (breadth-first), so the border keeps
/// matching its face. `log_gain`: the corrections are log gains (pixel * exp(g)), else offsets.
void applyChartCorrection(const Chart& chart,
                          const std::vector<std::array<Eigen::Vector2f, 3>>& face_pixels,
                          const std::vector<std::array<Vec3f, 3>>& corner_correction,
                          cv::Mat& page, bool log_gain = false);

/// Texture coordinates of every face corner in OBJ convention (u right, v up, (0,0) the
/// bottom-left corner of the page, pixel centres at (i + 0.5) / size), and the page of each
/// face. Faces without a chart map to the centre of their palette cell `face_fill_cell[f]`
/// (cell 0 if the vector is empty).
void faceUvs(const AtlasLayout& layout,
             const std::vector<std::array<Eigen::Vector2f, 3>>& face_pixels,
             std::vector<std::array<Eigen::Vector2f, 3>>& uvs, std::vector<std::uint32_t>& pages,
             const std::vector<std::uint32_t>& face_fill_cell = {});

/// Top-left pixel of palette cell `cell` in its page.
inline RectPlacement fillCellOrigin(const AtlasLayout& layout, int cell) {
    return {layout.fill_place.page, layout.fill_place.x + (cell % kFillColumns) * kFillCellPx,
            layout.fill_place.y + (cell / kFillColumns) * kFillCellPx};
}

}  // namespace vdbmap::texture
