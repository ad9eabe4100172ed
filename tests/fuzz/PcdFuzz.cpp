// SPDX-License-Identifier: Apache-2.0
// PCD point clouds: ascii, binary and binary_compressed (LZF), the header and every field type.
#include "FuzzSupport.h"
#include "vdbmap/io/PointCloudIO.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    const auto path = fuzz::writeInput("scan.pcd", fuzz::asText(data, size));
    fuzz::refusesOnlyWithTypedErrors([&] {
        const PointCloud cloud = readPcd(path);
        if (!cloud.intensity.empty() && cloud.intensity.size() != cloud.points.size()) {
            std::abort();
        }
    });
    return 0;
}
