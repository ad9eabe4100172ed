// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <vector>

namespace vdbmap::detail {

/// Exact minimiser of a graph-representable binary energy (Kolmogorov and Zabih 2004):
///   E(x) = sum_v U_v(x_v) + sum_(v,u) c_vu [x_v = 0 and x_u = 1],  x_v in {0, 1}, c_vu >= 0,
/// by an s-t minimum cut: Boost Graph's Boykov-Kolmogorov max-flow on a compressed sparse row
/// graph, the source side (x = 0) being the vertices of the source search tree at the end,
/// i.e. those reachable from the source in the residual graph.
class BinaryCut {
public:
    /// Starts a new energy over `num_vars` variables (buffers are kept between problems).
    void reset(std::size_t num_vars);
    /// Adds the unary terms U_v(0) = cost0, U_v(1) = cost1.
    void addUnary(std::size_t v, double cost0, double cost1);
    /// Adds c [x_v = 0 and x_u = 1], c >= 0 (a zero c is ignored).
    void addPair(std::size_t v, std::size_t u, double c);
    /// Minimises E; x[v] = 0 or 1. Returns the minimum of E up to the constant dropped by the
    /// reparametrisation (min(U_v(0), U_v(1)) per variable is added back).
    double solve(std::vector<char>& x);

private:
    struct Arc {
        std::size_t from, to;
        double capacity;
    };
    std::size_t num_vars_ = 0;
    std::vector<double> cost0_, cost1_;
    std::vector<Arc> pairs_;
};

}  // namespace vdbmap::detail
