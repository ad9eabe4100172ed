// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>

#include "vdbmap/core/Types.h"

namespace vdbmap::detail {

/// Keeps, in order, the points of `cloud` (and their intensities, when it has them) for which
/// keep(i) is true; `i` is the point's index before the call. The scan filters of the
/// integrating stage (moving objects, a process's region) drop points through it.
template <typename Keep>
void keepPoints(PointCloud& cloud, Keep&& keep) {
    const bool has_intensity = cloud.intensity.size() == cloud.points.size();
    std::size_t kept = 0;
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        if (!keep(i)) continue;
        cloud.points[kept] = cloud.points[i];
        if (has_intensity) cloud.intensity[kept] = cloud.intensity[i];
        ++kept;
    }
    cloud.points.resize(kept);
    if (has_intensity) cloud.intensity.resize(kept);
}

}  // namespace vdbmap::detail
