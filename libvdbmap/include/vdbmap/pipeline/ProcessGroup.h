// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace vdbmap {

/// The processes of one distributed run (the ranks of an MPI job) as the pipeline sees them.
/// The library never links MPI: `vdbmap-mpi` implements this on MPI (apps/vdbmap-mpi), and a
/// single-process run uses LocalProcessGroup. Every call except rank() and size() is
/// collective: each process makes the same calls in the same order. Implementations throw
/// Error when the transport fails.
class ProcessGroup {
public:
    virtual ~ProcessGroup() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    /// Every process's `mine`, in rank order, on every process.
    virtual std::vector<std::string> allGather(const std::string& mine) = 0;
    /// Process 0 gets every process's `mine` through `receive(rank, bytes)`, in rank order and
    /// one at a time (so that it can merge and free each before the next arrives); the others
    /// only send. Parts may be larger than 2 GiB.
    virtual void gatherToRoot(std::string mine,
                              const std::function<void(int, std::string&&)>& receive) = 0;
};

/// The one process of a run without MPI.
class LocalProcessGroup final : public ProcessGroup {
public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    std::vector<std::string> allGather(const std::string& mine) override { return {mine}; }
    void gatherToRoot(std::string mine,
                      const std::function<void(int, std::string&&)>& receive) override {
        receive(0, std::move(mine));
    }
};

}  // namespace vdbmap
