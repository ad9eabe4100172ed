// SPDX-License-Identifier: Apache-2.0
#include "AtlasPacker.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "vdbmap/Error.h"

namespace vdbmap::texture {

PackResult packRects(const std::vector<RectSize>& sizes, int max_size_px) {
    PackResult result;
    result.placements.resize(sizes.size());
    if (sizes.empty()) return result;
    if (max_size_px <= 0) {
        throw InvalidInput("packRects: max_size_px must be positive, got " +
                           std::to_string(max_size_px));
    }
    double total_area = 0;
    int widest = 0;
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        const RectSize& s = sizes[i];
        if (s.width <= 0 || s.height <= 0 || s.width > max_size_px || s.height > max_size_px) {
            throw InvalidInput("packRects: rectangle " + std::to_string(i) + " is " +
                               std::to_string(s.width) + " x " + std::to_string(s.height) +
                               " px; it must be non-empty and at most " +
                               std::to_string(max_size_px) + " px");
        }
        total_area += double(s.width) * s.height;
        widest = std::max(widest, s.width);
    }
    // Shelf packing loses ~10-20 %: aim the page width at the area with some slack.
    int page_width = 64;
    while (page_width < max_size_px && double(page_width) * page_width < 1.25 * total_area) {
        page_width *= 2;
    }
    page_width = std::min(std::max(page_width, widest), max_size_px);

    std::vector<std::size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return sizes[a].height > sizes[b].height;
    });
    int page = 0, shelf_y = 0, shelf_height = 0, cursor_x = 0;
    result.pages.push_back({page_width, 0});
    for (const std::size_t i : order) {
        const RectSize& s = sizes[i];
        if (cursor_x + s.width > page_width) {  // next shelf
            shelf_y += shelf_height;
            shelf_height = 0;
            cursor_x = 0;
        }
        if (shelf_y + s.height > max_size_px) {  // next page
            ++page;
            shelf_y = 0;
            shelf_height = 0;
            cursor_x = 0;
            result.pages.push_back({page_width, 0});
        }
        result.placements[i] = {page, cursor_x, shelf_y};
        cursor_x += s.width;
        shelf_height = std::max(shelf_height, s.height);
        result.pages[page].height = std::max(result.pages[page].height, shelf_y + s.height);
    }
    return result;
}

}  // namespace vdbmap::texture
