// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <chrono>

namespace vdbmap {

/// Wall-clock stopwatch (steady clock), seconds as double.
class Timer {
public:
    Timer() : start_(Clock::now()) {}
    void reset() { start_ = Clock::now(); }
    double elapsedSeconds() const {
        return std::chrono::duration<double>(Clock::now() - start_).count();
    }

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point start_;
};

/// Peak resident set size of this process in bytes (from /proc/self/status VmHWM; 0 if unknown).
std::size_t peakMemoryBytes();

}  // namespace vdbmap
