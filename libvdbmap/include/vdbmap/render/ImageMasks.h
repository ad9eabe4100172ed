// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "vdbmap/render/Visibility.h"

namespace vdbmap {

class Dataset;

/// The mask of a view's image: CV_8UC1 of the image's size, non-zero where the image must not
/// give a face its colour (a moving object a 2D detector found, the ego vehicle's bonnet), or
/// an empty Mat when the view has no mask.
using ViewMaskFn = std::function<cv::Mat(std::size_t view)>;

/// Removes the observations (face, view) of `vis` whose face touches a masked pixel of the
/// view: any of its four samples (the centroid of the projected corners and the corners pulled
/// 30 % towards it, as the scan occlusion test) within `dilate_px` (Chebyshev distance) of a
/// non-zero pixel of mask_of_view(view). Keeps the order of the remaining observations. Returns
/// how many were removed. Parallel over views; the result does not depend on the thread count.
/// Throws InvalidInput on dilate_px outside [0, 32], an observation of a view outside
/// `views`, or a mask that is not CV_8UC1 of its view's image size.
std::size_t removeMaskedObservations(Visibility& vis, const std::vector<View>& views,
                                     const ViewMaskFn& mask_of_view, int dilate_px);

/// The masks of `views` in `dir`: the file with the name of the view's image, in `dir` when the
/// dataset has one camera and in `dir`/<camera name> with several. A view without such a file
/// has no mask. A mask is read as 8-bit grey; one that cannot be read, or whose size is not its
/// image's, throws IoError naming the file, its size and the expected one. Throws IoError if
/// `dir` is not a directory.
ViewMaskFn directoryViewMasks(const Dataset& dataset, const std::vector<View>& views,
                              const std::filesystem::path& dir);

}  // namespace vdbmap
