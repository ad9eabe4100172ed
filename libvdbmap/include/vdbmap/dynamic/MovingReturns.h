// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// The LiDAR returns a run removed as moving (docs/dynamic.md), per frame, in the world frame W
/// (metres): what stood in front of the cameras at that frame and is not in the static map.
/// The texture and semantic stages' scan occlusion hides a face behind them by a tighter rule
/// than behind any return (ScanOcclusionOptions::moving_margin_m): they cannot be the face's
/// own surface, so a passing car's tyres do not texture the road they stand on.
///
/// integrate.atsdf fills it as it decides each scan (in its read-ahead task, while a streamed
/// tiled run finishes tiles from it): add() and frame() may run on different threads.
class MovingReturns {
public:
    /// Sets frame `frame`'s moving returns (replaces what it had).
    void set(std::size_t frame, std::vector<Vec3f> points_W);
    /// A copy of frame `frame`'s moving returns (empty: none, or not decided yet).
    std::vector<Vec3f> frame(std::size_t frame) const;
    /// Returns held, over every frame.
    std::size_t size() const;

private:
    mutable std::mutex mutex_;
    std::unordered_map<std::size_t, std::vector<Vec3f>> by_frame_;
    std::size_t size_ = 0;
};

}  // namespace vdbmap
