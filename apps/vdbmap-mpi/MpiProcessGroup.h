// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <mpi.h>

#include "vdbmap/pipeline/ProcessGroup.h"

namespace vdbmap {

/// ProcessGroup on MPI_COMM_WORLD (Open MPI). Only the main thread calls MPI
/// (MPI_THREAD_FUNNELED; TBB's workers never do). Throws Error naming the call when MPI
/// returns an error.
class MpiProcessGroup final : public ProcessGroup {
public:
    MpiProcessGroup();
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    std::vector<std::string> allGather(const std::string& mine) override;
    void gatherToRoot(std::string mine,
                      const std::function<void(int, std::string&&)>& receive) override;

private:
    int rank_ = 0;
    int size_ = 1;
};

}  // namespace vdbmap
