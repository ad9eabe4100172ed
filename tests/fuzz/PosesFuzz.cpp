// SPDX-License-Identifier: Apache-2.0
// Pose files: every input goes to the KITTI reader (12 numbers a line) and the TUM reader
// (t tx ty tz qx qy qz qw). A pose that is read must be finite and rigid.
#include <cstdlib>

#include "FuzzSupport.h"
#include "vdbmap/io/PoseIO.h"

namespace {
void requireRigid(const vdbmap::Isometry3d& T) {
    const vdbmap::Mat3d R = T.linear();
    if (!T.matrix().allFinite()) std::abort();
    if ((R.transpose() * R - vdbmap::Mat3d::Identity()).cwiseAbs().maxCoeff() > 1e-2) std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    const auto path = fuzz::writeInput("poses.txt", fuzz::asText(data, size));
    fuzz::refusesOnlyWithTypedErrors([&] {
        for (const Isometry3d& T : readKittiPoses(path)) requireRigid(T);
    });
    fuzz::refusesOnlyWithTypedErrors([&] {
        for (const StampedPose& p : readTumPoses(path)) requireRigid(p.T_W_S);
    });
    return 0;
}
