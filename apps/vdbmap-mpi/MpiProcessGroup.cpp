// SPDX-License-Identifier: Apache-2.0
#include "MpiProcessGroup.h"

#include <algorithm>
#include <climits>
#include <cstdint>

#include "vdbmap/Error.h"

namespace vdbmap {
namespace {

constexpr int kTagSize = 1;
constexpr int kTagBytes = 2;
// MPI counts are ints: large parts travel in chunks.
constexpr std::size_t kChunkBytes = std::size_t(1) << 30;

void check(int code, const char* call) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw Error(std::string("MPI: ") + call + " failed: " + std::string(text, static_cast<std::size_t>(length)));
}

int intCount(std::size_t n, const char* what) {
    if (n > static_cast<std::size_t>(INT_MAX)) {
        throw Error(std::string("MPI: ") + what + " of " + std::to_string(n) + " bytes exceeds 2 GiB");
    }
    return static_cast<int>(n);
}

}  // namespace

MpiProcessGroup::MpiProcessGroup() {
    check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
}

std::vector<std::string> MpiProcessGroup::allGather(const std::string& mine) {
    const int n = intCount(mine.size(), "allGather message");
    std::vector<int> sizes(static_cast<std::size_t>(size_));
    check(MPI_Allgather(&n, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    std::vector<int> offsets(static_cast<std::size_t>(size_), 0);
    std::size_t total = 0;
    for (std::size_t r = 0; r < sizes.size(); ++r) {
        offsets[r] = intCount(total, "allGather total");
        total += static_cast<std::size_t>(sizes[r]);
    }
    std::string all(total, '\0');
    check(MPI_Allgatherv(mine.data(), n, MPI_CHAR, all.data(), sizes.data(), offsets.data(),
                         MPI_CHAR, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    std::vector<std::string> out;
    for (std::size_t r = 0; r < sizes.size(); ++r) {
        out.push_back(all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(sizes[r])));
    }
    return out;
}

void MpiProcessGroup::gatherToRoot(std::string mine,
                                   const std::function<void(int, std::string&&)>& receive) {
    if (rank_ != 0) {
        const std::uint64_t n = mine.size();
        check(MPI_Send(&n, 1, MPI_UINT64_T, 0, kTagSize, MPI_COMM_WORLD), "MPI_Send");
        for (std::size_t at = 0; at < mine.size(); at += kChunkBytes) {
            const std::size_t chunk = std::min(kChunkBytes, mine.size() - at);
            check(MPI_Send(mine.data() + at, static_cast<int>(chunk), MPI_CHAR, 0, kTagBytes,
                           MPI_COMM_WORLD),
                  "MPI_Send");
        }
        return;
    }
    receive(0, std::move(mine));
    // One process at a time, in rank order: process 0 holds one part besides what it merged.
    for (int r = 1; r < size_; ++r) {
        std::uint64_t n = 0;
        check(MPI_Recv(&n, 1, MPI_UINT64_T, r, kTagSize, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
        std::string part(static_cast<std::size_t>(n), '\0');
        for (std::size_t at = 0; at < part.size(); at += kChunkBytes) {
            const std::size_t chunk = std::min(kChunkBytes, part.size() - at);
            check(MPI_Recv(part.data() + at, static_cast<int>(chunk), MPI_CHAR, r, kTagBytes,
                           MPI_COMM_WORLD, MPI_STATUS_IGNORE),
                  "MPI_Recv");
        }
        receive(r, std::move(part));
    }
}

}  // namespace vdbmap
