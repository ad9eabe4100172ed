// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/core/Timer.h"

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <string>

namespace vdbmap {
namespace {

/// The peak of the windows before the last reset.
std::atomic<std::size_t> g_earlier_peak{0};

}  // namespace

std::size_t windowPeakMemoryBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) {
            return static_cast<std::size_t>(std::stoull(line.substr(6))) * 1024;  // kB
        }
    }
    return 0;
}

std::size_t peakMemoryBytes() { return std::max(g_earlier_peak.load(), windowPeakMemoryBytes()); }

bool resetPeakMemoryWindow() {
    const std::size_t before = windowPeakMemoryBytes();
    std::size_t earlier = g_earlier_peak.load();
    while (before > earlier && !g_earlier_peak.compare_exchange_weak(earlier, before)) {
    }
    std::ofstream clear("/proc/self/clear_refs");
    if (!clear) return false;
    clear << "5";
    clear.flush();
    return static_cast<bool>(clear);
}

double processCpuTimeS() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto seconds = [](const timeval& t) {
        return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

}  // namespace vdbmap
