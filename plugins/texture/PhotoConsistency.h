// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "TextureTypes.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::texture {

/// Options of the photo-consistency check (Waechter et al. 2014, in HSV as the paper says).
struct PhotoConsistencyOptions {
    int min_views = 3;          ///< faces with fewer candidate views are left alone
    double max_distance = 2.5;  ///< reject a view farther than this many (robust) sigmas
    double min_sigma = 0.04;    ///< floor of the per-axis spread, HSV-cone units (0..1)
    int iterations = 10;        ///< mean-shift iterations
};

/// A BGR colour (0..255) in the HSV cone: (s cos h, s sin h, v), all in [-1, 1]. The cone
/// avoids the hue wrap-around, and hue means nothing for grey colours (s = 0).
Vec3f bgrToHsvCone(const Vec3f& bgr);

/// The photo-consistency check for one face: the colours of the face in its candidate views
/// (BGR, 0..255). Returns one flag per colour, true for the views kept. The majority is
/// assumed right (paper): a mean shift with a Gaussian kernel, started at the per-axis median
/// with a spread of 1.4826 * MAD (floored at min_sigma), finds the dominant mode; views
/// farther than max_distance from it are outliers (e.g. a pedestrian seen by a few views).
/// At least one view is always kept.
std::vector<char> photoConsistentViews(const std::vector<Vec3f>& colors_bgr,
                                       const PhotoConsistencyOptions& options);

/// Runs the check on every face; `keep[obs]` is set to 0 for rejected observations (entries
/// already 0 stay 0). Returns the number of observations rejected. Parallel over faces.
std::size_t applyPhotoConsistency(const Visibility& vis, const std::vector<ObservationStats>& stats,
                                  const PhotoConsistencyOptions& options, std::vector<char>& keep);

}  // namespace vdbmap::texture
