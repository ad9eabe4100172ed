// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <vector>

namespace vdbmap::texture {

/// Width and height of a rectangle in pixels.
struct RectSize {
    int width = 0;
    int height = 0;
};

/// Where a rectangle went: atlas page and top-left pixel.
struct RectPlacement {
    int page = 0;
    int x = 0;
    int y = 0;
};

/// Result of packRects: one placement per input rectangle and the size of each page.
struct PackResult {
    std::vector<RectPlacement> placements;
    std::vector<RectSize> pages;
};

/// Shelf packer: rectangles sorted by height (then index) fill shelves left to right; a
/// page is square-ish (width = the power of two that fits the total area, at most
/// `max_size_px`), and a new page starts when the current one would exceed max_size_px in
/// height. Rectangles never overlap. Page heights are trimmed to what is used. Throws
/// InvalidInput if a rectangle is empty or larger than max_size_px.
PackResult packRects(const std::vector<RectSize>& sizes, int max_size_px);

}  // namespace vdbmap::texture
