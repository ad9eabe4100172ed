// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <unordered_map>
#include <vector>

namespace vdbmap {
class Dataset;
class DynamicDetector;
}  // namespace vdbmap

namespace vdbmap::detail {

/// The moving points of the scans of a distributed run (issue 37), each scan tested by one
/// process for all of them. Neighbouring processes integrate many of the same scans (a scan
/// reaches 120 m, a process's tiles span a few hundred metres of the drive), and the
/// moving-object test was most of what they repeated. The detector's decision for a scan
/// depends only on the dataset (DynamicDetector), so a scan decided by another process drops
/// the same points: tiles and map.vdb stay those of the single-process run (MpiRunTest).
///
/// Every process calls decide() on its share of the frames, then the parts travel to every
/// process (ProcessGroup::allGather) and adopt() keeps the decisions of the frames it
/// integrates. A process that failed in decide() sends its error instead: the others then
/// test its frames themselves (flags() has no answer for them), and the failing process
/// rethrows its own error from adopt(), so the run fails with its error (PipelineRunner).
class SharedDynamicDecisions {
public:
    /// Tests `frames` (ascending), each scan read as the integrating stage reads it
    /// (Dataset::loadScan with the file indices), and returns this process's part: the file
    /// indices of each frame's moving points, or the error that stopped it.
    std::string decide(const Dataset& dataset, DynamicDetector& detector,
                       const std::vector<std::size_t>& frames);
    /// Takes the decisions of every process's part for the frames in `keep` (ascending);
    /// rethrows the error decide() met here, if any.
    void adopt(const std::vector<std::string>& parts, const std::vector<std::size_t>& keep);
    /// The flags (1 = moving) of frame `frame`'s points, given their file indices `index`:
    /// false if no process decided the frame.
    bool flags(std::size_t frame, const std::vector<std::uint32_t>& index,
               std::vector<std::uint8_t>& out) const;
    /// Frames this process tested for all / frames it took from the others' parts.
    std::size_t decidedHere() const { return decided_here_; }
    std::size_t adopted() const { return adopted_; }

private:
    /// Frame -> file indices of its moving points, ascending.
    std::unordered_map<std::size_t, std::vector<std::uint32_t>> moving_;
    std::exception_ptr failure_;
    std::size_t decided_here_ = 0, adopted_ = 0;
};

}  // namespace vdbmap::detail
