// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace vdbmap {

class Dataset;
namespace detail {
class PointRegion;
}

/// The pipeline's side of scan streaming (Context::beginScanStream / scanIntegrated): the
/// tiled pipeline plans its tiles when the integrating stage begins and finishes them as the
/// frames they wait for are integrated (pipeline/TileStream.h).
class ScanStream {
public:
    virtual ~ScanStream() = default;
    /// Plans with the stage's update reach; returns the frames to integrate, ascending.
    virtual std::vector<std::size_t> begin(const Dataset& dataset, double update_reach_m) = 0;
    virtual void frameIntegrated(std::size_t frame) = 0;
    virtual bool begun() const = 0;
    /// The frames begin() returned.
    virtual const std::vector<std::size_t>& frames() const = 0;
    /// This process and the number of processes of a distributed run (0 and 1 otherwise).
    virtual int process() const { return 0; }
    virtual int processes() const { return 1; }
    /// A process of a distributed run: the ground its points must fall in to change its tiles
    /// (after begin(); nullptr: every point matters).
    virtual const detail::PointRegion* pointRegion() const { return nullptr; }
    /// A process of a distributed run (after begin()): the frames whose per-scan work (the
    /// moving-object test) it does for every process: the frames any process integrates, cut
    /// into equal contiguous runs (issue 37). Empty otherwise.
    virtual std::vector<std::size_t> sharedFrames() const { return {}; }
    /// Every process's `mine`, in process order; a collective: every process calls it at the
    /// same point. One process: {mine}.
    virtual std::vector<std::string> allGather(const std::string& mine) const { return {mine}; }
};

}  // namespace vdbmap
