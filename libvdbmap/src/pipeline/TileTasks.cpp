// SPDX-License-Identifier: Apache-2.0
#include "pipeline/TileTasks.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <memory>
#include <string>

#include "vdbmap/core/Timer.h"

namespace vdbmap::detail {

TileTasks::TileTasks(std::size_t max_in_flight, std::size_t budget_bytes,
                     std::function<std::size_t()> base_bytes,
                     std::function<std::size_t()> growth_bytes)
    : max_in_flight_(std::max<std::size_t>(1, max_in_flight)), budget_bytes_(budget_bytes),
      base_bytes_(std::move(base_bytes)), growth_bytes_(std::move(growth_bytes)) {}

TileTasks::~TileTasks() { abandon(); }

void TileTasks::joinFinished() {
    for (auto it = tasks_.begin(); it != tasks_.end();) {
        if ((*it)->done) {
            if ((*it)->thread.joinable()) (*it)->thread.join();
            it = tasks_.erase(it);
        } else {
            ++it;
        }
    }
}

void TileTasks::rethrowIfFailed(std::unique_lock<std::mutex>& lock) {
    if (!failure_) return;
    changed_.wait(lock, [&] { return in_flight_ == 0; });
    joinFinished();
    std::rethrow_exception(failure_);
}

void TileTasks::launch(std::size_t estimate_bytes, std::function<void(std::string& at)> work) {
    std::unique_lock<std::mutex> lock(mutex_);
    joinFinished();
    rethrowIfFailed(lock);
    if (in_flight_ == 0) {
        sampleBase();
    } else {
        updateBase();
    }
    auto fits = [&] {
        if (failure_) return true;
        if (in_flight_ == 0) return true;  // one tile always runs, whatever its estimate
        return in_flight_ < max_in_flight_ && base_ + estimates_ + estimate_bytes <= budget_bytes_;
    };
    if (!fits()) {
        Timer waited;
        ++figures_.waits;
        changed_.wait(lock, fits);
        figures_.wait_s += waited.elapsedSeconds();
        joinFinished();
        rethrowIfFailed(lock);
        if (in_flight_ == 0) sampleBase();
    }
    {
        const std::array<std::size_t, 2> heap = allocatorBytes();
        figures_.at_launch.push_back({currentRssBytes(), heap[0], heap[1], estimates_, base_});
    }
    ++in_flight_;
    estimates_ += estimate_bytes;
    ++figures_.tasks;
    figures_.max_in_flight = std::max(figures_.max_in_flight, in_flight_);
    figures_.max_estimate_bytes = std::max(figures_.max_estimate_bytes, base_ + estimates_);
    auto task = std::make_unique<Task>();
    task->estimate = estimate_bytes;
    Task* raw = task.get();
    tasks_.push_back(std::move(task));
    raw->thread = std::thread([this, raw, work = std::move(work)] {
        std::string at;
        std::exception_ptr error;
        try {
            work(at);
        } catch (...) {
            error = std::current_exception();
        }
        releaseFreedMemory();  // the tile's mesh, views and images are freed by now
        std::lock_guard<std::mutex> done_lock(mutex_);
        if (error && !failure_) {
            failure_ = error;
            failed_at_ = at;
        }
        raw->done = true;
        --in_flight_;
        estimates_ -= raw->estimate;
        changed_.notify_all();
    });
}

void TileTasks::sampleBase() {
    base_sample_ = base_bytes_ ? base_bytes_() : 0;
    growth_at_sample_ = growth_bytes_ ? growth_bytes_() : 0;
    base_ = base_sample_;
    figures_.base_samples.push_back(base_);
}

void TileTasks::updateBase() {
    const std::size_t growth = growth_bytes_ ? growth_bytes_() : 0;
    base_ = base_sample_ + (growth > growth_at_sample_ ? growth - growth_at_sample_ : 0);
}

void TileTasks::poll() {
    std::unique_lock<std::mutex> lock(mutex_);
    joinFinished();
    rethrowIfFailed(lock);
}

void TileTasks::waitAll() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return in_flight_ == 0; });
    joinFinished();
    rethrowIfFailed(lock);
}

void TileTasks::abandon() noexcept {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return in_flight_ == 0; });
    joinFinished();
    failure_ = nullptr;
}

std::string TileTasks::failedAt() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return failed_at_;
}

TileTasks::Figures TileTasks::figures() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return figures_;
}

namespace {
/// The value (kB in the file) of `key` in a /proc file, bytes.
std::size_t procKb(const char* file, const std::string& key) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind(key, 0) == 0) return static_cast<std::size_t>(std::stoull(line.substr(key.size()))) * 1024;
    }
    return 0;
}
}  // namespace

void releaseFreedMemory() {
#if defined(__GLIBC__)
    static const bool off = [] {
        const char* v = std::getenv("VDBMAP_MALLOC_TRIM");
        return v != nullptr && std::strcmp(v, "0") == 0;
    }();
    if (!off) ::malloc_trim(0);
#endif
}

std::array<std::size_t, 2> allocatorBytes() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
    const struct mallinfo2 m = ::mallinfo2();
    return {m.uordblks + m.hblkhd, m.fordblks};
#else
    return {0, 0};
#endif
}

std::size_t currentRssBytes() { return procKb("/proc/self/status", "VmRSS:"); }

std::size_t memAvailableBytes() { return procKb("/proc/meminfo", "MemAvailable:"); }

}  // namespace vdbmap::detail
