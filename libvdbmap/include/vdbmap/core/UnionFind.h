// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

namespace vdbmap {

/// Disjoint-set forest over 0..n-1 stored as a parent array (parent[i] == i for a root), as
/// used for mesh components, MRF components, texture patches and unseen semantic regions.

/// Root of x's set, halving the path on the way (amortised near-constant time).
inline std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/// A parent array of n singletons.
inline std::vector<std::uint32_t> makeDisjointSets(std::size_t n) {
    std::vector<std::uint32_t> parent(n);
    for (std::size_t i = 0; i < n; ++i) parent[i] = static_cast<std::uint32_t>(i);
    return parent;
}

}  // namespace vdbmap
