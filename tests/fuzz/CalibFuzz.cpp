// SPDX-License-Identifier: Apache-2.0
// Calibration files: every input goes to the KITTI calib.txt reader (P0..P3, Tr) and to the
// generic camera file reader (K:, D:, T:).
#include "FuzzSupport.h"
#include "vdbmap/io/CalibIO.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    const auto path = fuzz::writeInput("calib.txt", fuzz::asText(data, size));
    fuzz::refusesOnlyWithTypedErrors([&] { readKittiCalib(path); });
    fuzz::refusesOnlyWithTypedErrors([&] { readCameraCalib(path); });
    return 0;
}
