// SPDX-License-Identifier: Apache-2.0
#include "stages/SharedDynamicDecisions.h"

#include <algorithm>
#include <cstring>

#include "vdbmap/Error.h"
#include "vdbmap/dynamic/DynamicDetector.h"
#include "vdbmap/io/Dataset.h"

namespace vdbmap::detail {
namespace {

constexpr char kDecided = 'D';  // a part: 'D', then per frame: frame, count, count indices
constexpr char kFailed = 'E';   // a part: 'E', then the error's message

template <typename T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
}

template <typename T>
T take(const std::string& in, std::size_t& at) {
    if (at + sizeof(T) > in.size()) {
        throw InvalidInput("moving-point decisions of another process: truncated part");
    }
    T value;
    std::memcpy(&value, in.data() + at, sizeof(T));
    at += sizeof(T);
    return value;
}

}  // namespace

std::string SharedDynamicDecisions::decide(const Dataset& dataset, DynamicDetector& detector,
                                           const std::vector<std::size_t>& frames) {
    std::string part(1, kDecided);
    try {
        PointCloud cloud;
        std::vector<std::uint32_t> index;
        for (const std::size_t frame : frames) {
            ScanReadStats stats;
            dataset.loadScan(frame, cloud, &stats, &index);
            const std::vector<std::uint8_t> moving =
                detector.detect(frame, cloud.points, index, stats.points_read);
            std::vector<std::uint32_t>& mine = moving_[frame];
            mine.clear();
            for (std::size_t i = 0; i < moving.size(); ++i)
                if (moving[i]) mine.push_back(index[i]);
            std::sort(mine.begin(), mine.end());
            put<std::uint64_t>(part, frame);
            put<std::uint64_t>(part, mine.size());
            for (const std::uint32_t k : mine) put<std::uint32_t>(part, k);
            ++decided_here_;
        }
    } catch (const std::exception& e) {
        failure_ = std::current_exception();
        moving_.clear();
        decided_here_ = 0;
        return std::string(1, kFailed) + e.what();
    }
    return part;
}

void SharedDynamicDecisions::adopt(const std::vector<std::string>& parts,
                                   const std::vector<std::size_t>& keep) {
    if (failure_) std::rethrow_exception(failure_);
    const auto wanted = [&](std::size_t frame) {
        return std::binary_search(keep.begin(), keep.end(), frame);
    };
    // This process's own decisions are in moving_ already; drop those it does not integrate.
    for (auto it = moving_.begin(); it != moving_.end();) {
        it = wanted(it->first) ? std::next(it) : moving_.erase(it);
    }
    for (const std::string& part : parts) {
        if (part.empty() || part[0] != kDecided) continue;  // failed: its frames are tested here
        std::size_t at = 1;
        while (at < part.size()) {
            const auto frame = static_cast<std::size_t>(take<std::uint64_t>(part, at));
            const auto count = static_cast<std::size_t>(take<std::uint64_t>(part, at));
            if (!wanted(frame) || moving_.count(frame)) {
                at += count * sizeof(std::uint32_t);
                continue;
            }
            std::vector<std::uint32_t>& indices = moving_[frame];
            indices.reserve(count);
            for (std::size_t i = 0; i < count; ++i) indices.push_back(take<std::uint32_t>(part, at));
            ++adopted_;
        }
    }
}

bool SharedDynamicDecisions::flags(std::size_t frame, const std::vector<std::uint32_t>& index,
                                   std::vector<std::uint8_t>& out) const {
    const auto it = moving_.find(frame);
    if (it == moving_.end()) return false;
    const std::vector<std::uint32_t>& moving = it->second;
    out.assign(index.size(), 0);
    for (std::size_t i = 0; i < index.size(); ++i) {
        out[i] = std::binary_search(moving.begin(), moving.end(), index[i]) ? 1 : 0;
    }
    return true;
}

}  // namespace vdbmap::detail
