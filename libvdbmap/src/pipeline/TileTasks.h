// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace vdbmap::detail {

/// Tiles in flight side by side (issue 37): each launched tile's remaining stages run on a
/// thread of their own (TBB's parallel loops inside it share the run's threads, as the
/// integrating thread's do), at most `max_in_flight` at once and, beyond the first, only while
/// the memory of the process without tiles plus the estimated peaks of the tiles in flight fit
/// `budget_bytes`. A plain thread, not a TBB task: a thread waiting inside a parallel loop of
/// the integration would otherwise steal a whole tile and stall the integration behind it.
///
/// A failing task's exception is kept; the next launch(), poll() or waitAll() waits for every
/// task in flight and rethrows the first failure (with what was running: `at`).
class TileTasks {
public:
    struct Figures {
        std::size_t max_in_flight = 0;        ///< most tasks running at once
        std::size_t max_estimate_bytes = 0;   ///< largest sum of in-flight estimates + base
        std::size_t tasks = 0;
        std::size_t waits = 0;                ///< launches that waited for a slot
        double wait_s = 0.0;                  ///< time launch() spent waiting
        /// The memory without tiles in flight, each time it was sampled (a launch with none
        /// in flight), in order: how the process's own memory grows along the drive.
        std::vector<std::size_t> base_samples;
        /// At each launch: the process's RSS, the bytes the allocator has handed out and not
        /// got back (glibc mallinfo2: arenas and mmapped chunks; 0 elsewhere), the free bytes
        /// it holds in its arenas, the estimates of the tiles in flight (without the one
        /// launched), and the memory without tiles the budget counted (the last sample plus
        /// the growth since): RSS minus the bytes in use is what the allocator retains.
        std::vector<std::array<std::size_t, 5>> at_launch;
    };
    /// `base_bytes()` gives the process's memory without tiles in flight (sampled when none
    /// is). `growth_bytes()` (optional) gives memory the process grows by with tiles in flight
    /// that no tile's estimate holds (the map): each launch counts the base as the last sample
    /// plus its growth since, as tiles are in flight from the first launch to the last on a
    /// streamed run and the base would otherwise be sampled only once.
    TileTasks(std::size_t max_in_flight, std::size_t budget_bytes,
              std::function<std::size_t()> base_bytes,
              std::function<std::size_t()> growth_bytes = {});
    ~TileTasks();  ///< waits for every task (errors dropped)
    TileTasks(const TileTasks&) = delete;
    TileTasks& operator=(const TileTasks&) = delete;

    /// Waits for a slot (count and memory), then runs `work` on a thread of its own. `work`
    /// sets `at` to what it runs (for the error report). Rethrows an earlier task's failure
    /// (after waiting for all) instead of launching.
    void launch(std::size_t estimate_bytes, std::function<void(std::string& at)> work);
    /// Rethrows a failure, if a task failed (after waiting for all); else returns at once.
    void poll();
    /// Waits for every task; rethrows the first failure.
    void waitAll();
    /// Waits for every task and forgets their failures (the run already fails).
    void abandon() noexcept;

    /// What the failing task ran when it failed ("" before a failure).
    std::string failedAt() const;
    Figures figures() const;
    std::size_t budgetBytes() const { return budget_bytes_; }

private:
    void joinFinished();  ///< joins the threads of finished tasks (lock held)
    void sampleBase();    ///< base_ = the memory now, recorded in the figures (lock held)
    void updateBase();    ///< base_ = the last sample plus the growth since (lock held)
    void rethrowIfFailed(std::unique_lock<std::mutex>& lock);

    struct Task {
        std::thread thread;
        bool done = false;
        std::size_t estimate = 0;
    };
    const std::size_t max_in_flight_;
    const std::size_t budget_bytes_;
    std::function<std::size_t()> base_bytes_;
    std::function<std::size_t()> growth_bytes_;
    std::size_t base_sample_ = 0;  ///< the process without tiles, sampled when none was in flight
    std::size_t growth_at_sample_ = 0;  ///< growth_bytes() when base_sample_ was taken
    std::size_t base_ = 0;  ///< base_sample_ plus the growth since (updated at each launch)
    std::size_t in_flight_ = 0;
    std::size_t estimates_ = 0;  ///< sum over the tasks in flight
    std::vector<std::unique_ptr<Task>> tasks_;
    mutable std::mutex mutex_;
    std::condition_variable changed_;
    std::exception_ptr failure_;
    std::string failed_at_;
    Figures figures_;
};

/// Gives the allocator's free pages back to the system (glibc: malloc_trim(0), every arena),
/// so that memory a finished tile freed is not counted again in the next tile's peak (issue
/// 37). VDBMAP_MALLOC_TRIM=0 in the environment turns it off (for measuring its effect).
void releaseFreedMemory();

/// The allocator's bytes in use and free bytes in its arenas (glibc mallinfo2); {0, 0} elsewhere.
std::array<std::size_t, 2> allocatorBytes();

/// The process's resident memory now (VmRSS), bytes; 0 if unknown.
std::size_t currentRssBytes();
/// MemAvailable of /proc/meminfo, bytes; 0 if unknown.
std::size_t memAvailableBytes();

}  // namespace vdbmap::detail
