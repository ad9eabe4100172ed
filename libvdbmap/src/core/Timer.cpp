// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/core/Timer.h"

#include <fstream>
#include <string>

namespace vdbmap {

std::size_t peakMemoryBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) {
            return static_cast<std::size_t>(std::stoull(line.substr(6))) * 1024;  // kB
        }
    }
    return 0;
}

}  // namespace vdbmap
