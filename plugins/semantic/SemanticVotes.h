// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <vector>

#include "vdbmap/io/LabelSet.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::semantic {

/// Accumulated class votes per face (paper Sec. 6, Eq. semantic_mrf_energy_function): for each
/// face, the classes seen at the centre pixel of its projection in the views where it is
/// visible, each weighted by the projected area S_Ik(F_i, C_m) in pixels^2. Classes are
/// indices into LabelSet::classes(). CSR over faces; classes ascending inside a face.
struct FaceVotes {
    std::size_t num_classes = 0;
    std::vector<std::uint64_t> offsets;  ///< size numFaces()+1
    std::vector<std::uint32_t> classes;  ///< class index
    std::vector<float> weights;          ///< accumulated projected area, px^2
    std::size_t votes = 0;               ///< observations that voted
    std::size_t void_votes = 0;          ///< observations whose centre pixel is 255 (void)
    std::size_t unknown_id_votes = 0;    ///< observations whose centre pixel is not in the set

    std::size_t numFaces() const { return offsets.empty() ? 0 : offsets.size() - 1; }
    /// True if at least one view voted for the face.
    bool observed(std::size_t face) const { return offsets[face + 1] > offsets[face]; }
};

/// Votes of every visible (face, view) pair. `label_images[v]` is the 8-bit id image of view v
/// (the view index of FaceObservation). The centre pixel is the centroid of the projected
/// corners, rounded to the nearest pixel (docs/DATA.md: (0,0) is the centre of the top-left pixel).
/// Void (255) and ids outside `labels` do not vote (counted). Parallel over faces,
/// deterministic. Throws InvalidInput if an observation refers to a missing view or an image
/// that is not 8-bit single channel.
FaceVotes accumulateVotes(const Visibility& visibility, const std::vector<cv::Mat>& label_images,
                          const LabelSet& labels);

/// The same with images loaded on demand, `chunk_views` views at a time (in parallel), so
/// that long sequences never hold all images in memory. `load(v)` returns the id image of
/// view v (it may throw, e.g. IoError). Same result as the overload above.
FaceVotes accumulateVotes(const Visibility& visibility, std::size_t num_views,
                          const std::function<cv::Mat(std::size_t)>& load,
                          const LabelSet& labels, std::size_t chunk_views = 64);

}  // namespace vdbmap::semantic
