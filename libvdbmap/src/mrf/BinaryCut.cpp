// SPDX-License-Identifier: Apache-2.0
// The s-t cut of an expansion move. OpenCV's cv::detail::GCGraph, used before, decides the side
// of a vertex from a tree flag that it leaves stale for the orphans it frees while adopting, so
// its cut could mix free vertices into the source side and not be a minimum cut (a move that
// should lower the energy was rejected, or a worse one proposed). Boost's implementation marks
// freed orphans as belonging to no tree.
#include "mrf/BinaryCut.h"

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>

#include <algorithm>
#include <numeric>
#include <utility>

namespace vdbmap::detail {

namespace {

using Graph = boost::compressed_sparse_row_graph<boost::directedS>;
using Vertex = boost::graph_traits<Graph>::vertex_descriptor;
using Edge = boost::graph_traits<Graph>::edge_descriptor;

/// The arcs of the flow network in CSR order (sorted by tail), each with its reverse.
struct Network {
    std::vector<std::pair<Vertex, Vertex>> ends;
    std::vector<double> capacity;
    std::vector<std::size_t> reverse;

    /// arcs: (from, to, capacity); every arc gets a reverse of capacity 0.
    template <class Arcs>
    Network(const Arcs& arcs, std::size_t num_vertices) {
        std::vector<std::size_t> next(num_vertices + 1, 0);
        for (const auto& a : arcs) {
            ++next[a.from + 1];
            ++next[a.to + 1];
        }
        std::partial_sum(next.begin(), next.end(), next.begin());
        const std::size_t m = 2 * arcs.size();
        ends.resize(m);
        capacity.assign(m, 0.0);
        reverse.resize(m);
        for (const auto& a : arcs) {
            const std::size_t f = next[a.from]++, b = next[a.to]++;
            ends[f] = {static_cast<Vertex>(a.from), static_cast<Vertex>(a.to)};
            ends[b] = {static_cast<Vertex>(a.to), static_cast<Vertex>(a.from)};
            capacity[f] = a.capacity;
            reverse[f] = b;
            reverse[b] = f;
        }
    }
};

}  // namespace

void BinaryCut::reset(std::size_t num_vars) {
    num_vars_ = num_vars;
    cost0_.assign(num_vars, 0.0);
    cost1_.assign(num_vars, 0.0);
    pairs_.clear();
}

void BinaryCut::addUnary(std::size_t v, double cost0, double cost1) {
    cost0_[v] += cost0;
    cost1_[v] += cost1;
}

void BinaryCut::addPair(std::size_t v, std::size_t u, double c) {
    if (c > 0.0) pairs_.push_back({v, u, c});
}

double BinaryCut::solve(std::vector<char>& x) {
    const std::size_t n = num_vars_;
    x.assign(n, 0);
    double constant = 0.0;
    if (pairs_.empty()) {
        for (std::size_t v = 0; v < n; ++v) {
            x[v] = cost1_[v] < cost0_[v];
            constant += std::min(cost0_[v], cost1_[v]);
        }
        return constant;
    }
    // Terminal arcs: x = 1 (sink side) cuts s -> v, so that arc carries U(1) - m; x = 0 cuts
    // v -> t, carrying U(0) - m, m = min(U(0), U(1)).
    const std::size_t source = n, sink = n + 1;
    std::vector<Arc> arcs = pairs_;
    for (std::size_t v = 0; v < n; ++v) {
        const double m = std::min(cost0_[v], cost1_[v]);
        constant += m;
        if (cost1_[v] > m) arcs.push_back({source, v, cost1_[v] - m});
        if (cost0_[v] > m) arcs.push_back({v, sink, cost0_[v] - m});
    }
    const Network net(arcs, n + 2);
    const Graph g(boost::edges_are_sorted, net.ends.begin(), net.ends.end(), n + 2);

    const auto edge_index = boost::get(boost::edge_index, g);
    const auto vertex_index = boost::get(boost::vertex_index, g);
    // Sorted input keeps the order: arc k is the CSR edge of index k.
    const std::size_t m = net.ends.size();
    std::vector<Edge> reverse(m);
    for (std::size_t k = 0; k < m; ++k) {
        const std::size_t r = net.reverse[k];
        reverse[k] = Edge(net.ends[r].first, r);
    }
    std::vector<double> residual(m, 0.0);
    std::vector<boost::default_color_type> colour(n + 2);
    std::vector<long> distance(n + 2, 0);
    std::vector<Edge> predecessor(n + 2);

    const double flow = boost::boykov_kolmogorov_max_flow(
        g, boost::make_iterator_property_map(net.capacity.begin(), edge_index),
        boost::make_iterator_property_map(residual.begin(), edge_index),
        boost::make_iterator_property_map(reverse.begin(), edge_index),
        boost::make_iterator_property_map(predecessor.begin(), vertex_index),
        boost::make_iterator_property_map(colour.begin(), vertex_index),
        boost::make_iterator_property_map(distance.begin(), vertex_index), vertex_index,
        static_cast<Vertex>(source), static_cast<Vertex>(sink));
    // Source tree (black) = reachable from s in the residual graph = the x = 0 side.
    for (std::size_t v = 0; v < n; ++v) {
        x[v] = colour[v] == boost::color_traits<boost::default_color_type>::black() ? 0 : 1;
    }
    return constant + flow;
}

}  // namespace vdbmap::detail
