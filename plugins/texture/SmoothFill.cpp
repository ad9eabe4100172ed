// SPDX-License-Identifier: Apache-2.0
#include "SmoothFill.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/core/UnionFind.h"

namespace vdbmap::texture {

std::vector<Vec3f> harmonicFill(const std::vector<char>& known, const std::vector<Vec3f>& color,
                                const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                std::vector<char>& filled,
                                const std::vector<float>* edge_weights) {
    const std::size_t n = known.size();
    if (color.size() != n) {
        throw InvalidInput("harmonicFill: " + std::to_string(color.size()) + " colours for " +
                           std::to_string(n) + " faces");
    }
    for (const auto& e : adjacency) {
        if (e[0] >= n || e[1] >= n) {
            throw InvalidInput("harmonicFill: adjacency pair (" + std::to_string(e[0]) + ", " +
                               std::to_string(e[1]) + ") out of range for " + std::to_string(n) +
                               " faces");
        }
    }
    if (edge_weights != nullptr && edge_weights->size() != adjacency.size()) {
        throw InvalidInput("harmonicFill: " + std::to_string(edge_weights->size()) +
                           " edge weights for " + std::to_string(adjacency.size()) + " edges");
    }
    // 1. Components with a textured face: only their untextured faces are unknowns.
    std::vector<std::uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    for (const auto& e : adjacency) {
        const std::uint32_t a = findRoot(parent, e[0]), b = findRoot(parent, e[1]);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
    std::vector<char> root_known(n, 0);
    for (std::size_t f = 0; f < n; ++f) {
        if (known[f]) root_known[findRoot(parent, static_cast<std::uint32_t>(f))] = 1;
    }
    std::vector<std::int64_t> unknown_index(n, -1);
    std::int64_t m = 0;
    filled.assign(n, 0);
    for (std::size_t f = 0; f < n; ++f) {
        if (known[f]) continue;
        if (!root_known[findRoot(parent, static_cast<std::uint32_t>(f))]) continue;
        unknown_index[f] = m++;
        filled[f] = 1;
    }
    std::vector<Vec3f> out(color);
    if (m == 0) return out;

    // 2. L_uu x_u = -L_uk x_k: degree on the diagonal, -1 per unknown neighbour, known
    //    neighbours move to the right-hand side.
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(4 * static_cast<std::size_t>(m) + adjacency.size());
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 3);
    std::vector<double> degree(static_cast<std::size_t>(m), 0.0);
    for (std::size_t k = 0; k < adjacency.size(); ++k) {
        const auto& e = adjacency[k];
        const std::int64_t a = unknown_index[e[0]], b = unknown_index[e[1]];
        if (a < 0 && b < 0) continue;
        const double w = edge_weights != nullptr ? (*edge_weights)[k] : 1.0;
        if (a >= 0) degree[a] += w;
        if (b >= 0) degree[b] += w;
        if (a >= 0 && b >= 0) {
            triplets.emplace_back(a, b, -w);
            triplets.emplace_back(b, a, -w);
        } else if (a >= 0) {
            rhs.row(a) += w * color[e[1]].cast<double>().transpose();
        } else {
            rhs.row(b) += w * color[e[0]].cast<double>().transpose();
        }
    }
    for (std::int64_t i = 0; i < m; ++i) triplets.emplace_back(i, i, degree[i]);
    Eigen::SparseMatrix<double> L(m, m);
    L.setFromTriplets(triplets.begin(), triplets.end());
    triplets.clear();
    triplets.shrink_to_fit();

    // 3. Sparse Cholesky (every component touches a fixed face, so L_uu is positive definite).
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(L);
    if (solver.info() != Eigen::Success) {
        throw InvalidInput("harmonicFill: the sparse factorisation of " + std::to_string(m) +
                           " unknowns failed");
    }
    const Eigen::MatrixXd x = solver.solve(rhs);
    for (std::size_t f = 0; f < n; ++f) {
        if (unknown_index[f] >= 0) out[f] = x.row(unknown_index[f]).transpose().cast<float>();
    }
    return out;
}

std::vector<float> creaseWeights(const std::vector<Vec3f>& vertices,
                                 const std::vector<std::array<std::uint32_t, 3>>& faces,
                                 const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                 double sigma_deg, double min_weight) {
    std::vector<Vec3f> normal(faces.size(), Vec3f::Zero());
    for (std::size_t f = 0; f < faces.size(); ++f) {
        for (const std::uint32_t v : faces[f]) {
            if (v >= vertices.size()) {
                throw InvalidInput("creaseWeights: face " + std::to_string(f) +
                                   " refers to vertex " + std::to_string(v));
            }
        }
        const Vec3f n = (vertices[faces[f][1]] - vertices[faces[f][0]])
                            .cross(vertices[faces[f][2]] - vertices[faces[f][0]]);
        if (n.norm() > 0.0f) normal[f] = n.normalized();
    }
    const double s = sigma_deg * M_PI / 180.0;
    std::vector<float> w(adjacency.size());
    for (std::size_t k = 0; k < adjacency.size(); ++k) {
        const auto [i, j] = adjacency[k];
        if (i >= faces.size() || j >= faces.size()) {
            throw InvalidInput("creaseWeights: adjacency pair " + std::to_string(k) +
                               " is out of range");
        }
        const double c = std::clamp(static_cast<double>(normal[i].dot(normal[j])), -1.0, 1.0);
        const double theta = std::acos(c);
        w[k] = static_cast<float>(std::max(min_weight, std::exp(-theta * theta / (2 * s * s))));
    }
    return w;
}

}  // namespace vdbmap::texture
