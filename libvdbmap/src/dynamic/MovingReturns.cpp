// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/MovingReturns.h"

namespace vdbmap {

void MovingReturns::set(std::size_t frame, std::vector<Vec3f> points_W) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Vec3f>& slot = by_frame_[frame];
    size_ -= slot.size();
    slot = std::move(points_W);
    size_ += slot.size();
}

std::vector<Vec3f> MovingReturns::frame(std::size_t frame) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_frame_.find(frame);
    return it == by_frame_.end() ? std::vector<Vec3f>{} : it->second;
}

std::size_t MovingReturns::size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return size_;
}

}  // namespace vdbmap
