// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>

namespace vdbmap {

/// visit(i) for every set bit i of `n_words` 64-bit words, in increasing order (bit i is bit
/// i % 64 of word i / 64: OpenVDB's node-mask layout).
template <typename Visit>
inline void forEachSetBit(const std::uint64_t* words, std::size_t n_words, Visit&& visit) {
    for (std::size_t w = 0; w < n_words; ++w)
        for (std::uint64_t bits = words[w]; bits != 0; bits &= bits - 1)
            visit(w * 64 + static_cast<std::size_t>(__builtin_ctzll(bits)));
}

}  // namespace vdbmap
