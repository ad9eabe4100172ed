// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace vdbmap {

/// Disjoint-set forest over 0..n-1 stored as a parent array (parent[i] == i for a root), as
/// used for mesh components, MRF components, texture patches and unseen semantic regions:
/// makeDisjointSets, then uniteSets per edge, then findRoot.

/// Root of x's set, halving the path on the way (amortised near-constant time).
inline std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/// Merges the sets of a and b. The smaller root becomes the root of both, so every root is
/// the smallest element of its set. Returns false if a and b were already in one set.
inline bool uniteSets(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
    a = findRoot(parent, a);
    b = findRoot(parent, b);
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
}

/// A parent array of n singletons.
inline std::vector<std::uint32_t> makeDisjointSets(std::size_t n) {
    std::vector<std::uint32_t> parent(n);
    for (std::size_t i = 0; i < n; ++i) parent[i] = static_cast<std::uint32_t>(i);
    return parent;
}

}  // namespace vdbmap
