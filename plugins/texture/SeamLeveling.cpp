// SPDX-License-Identifier: Apache-2.0
#include "SeamLeveling.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>

#include "vdbmap/Error.h"
#include "vdbmap/mrf/PottsMrf.h"

namespace vdbmap::texture {

std::vector<SeamEdge> findSeamEdges(const MeshArrays& mesh,
                                    const std::vector<std::uint32_t>& face_patch,
                                    const std::vector<std::array<std::uint32_t, 2>>& adjacency) {
    std::vector<SeamEdge> seams;
    for (const auto& [a, b] : adjacency) {
        if (a >= face_patch.size() || b >= face_patch.size()) {
            throw InvalidInput("texture: adjacency refers to a face beyond " +
                               std::to_string(face_patch.size()));
        }
        if (face_patch[a] == kNoLabel || face_patch[b] == kNoLabel) continue;
        if (face_patch[a] == face_patch[b]) continue;
        const auto& fa = mesh.faces[a];
        const auto& fb = mesh.faces[b];
        std::uint32_t shared[2];
        int count = 0;
        for (std::uint32_t va : fa) {
            if (count < 2 && std::find(fb.begin(), fb.end(), va) != fb.end()) shared[count++] = va;
        }
        if (count == 2) seams.push_back({a, b, shared[0], shared[1]});
    }
    return seams;
}

SeamSpace parseSeamSpace(const std::string& name) {
    if (name == "bgr") return SeamSpace::kBgr;
    if (name == "log_bgr") return SeamSpace::kLogBgr;
    if (name == "log_luminance") return SeamSpace::kLogLuminance;
    throw InvalidInput("texture: seam levelling space must be 'bgr', 'log_bgr' or 'log_luminance', got '" +
                       name + "'");
}

namespace {

/// A seam sample in the levelling space (all three channels equal for log luminance).
Vec3f toSpace(const Vec3f& bgr, SeamSpace space) {
    auto safeLog = [](float x) { return std::log(std::max(x, 1.0f)); };
    switch (space) {
        case SeamSpace::kBgr:
            return bgr;
        case SeamSpace::kLogBgr:
            return Vec3f(safeLog(bgr[0]), safeLog(bgr[1]), safeLog(bgr[2]));
        case SeamSpace::kLogLuminance:
            return Vec3f::Constant(safeLog(0.114f * bgr[0] + 0.587f * bgr[1] + 0.299f * bgr[2]));
    }
    return bgr;
}

/// Sorted (patch, vertex) keys: the unknowns of the adjustment.
class UnknownIndex {
public:
    void add(std::uint32_t patch, std::uint32_t vertex) { keys_.push_back(key(patch, vertex)); }
    void finalize() {
        std::sort(keys_.begin(), keys_.end());
        keys_.erase(std::unique(keys_.begin(), keys_.end()), keys_.end());
    }
    std::size_t size() const { return keys_.size(); }
    std::size_t find(std::uint32_t patch, std::uint32_t vertex) const {
        return static_cast<std::size_t>(
            std::lower_bound(keys_.begin(), keys_.end(), key(patch, vertex)) - keys_.begin());
    }

private:
    static std::uint64_t key(std::uint32_t patch, std::uint32_t vertex) {
        return (std::uint64_t(patch) << 32) | vertex;
    }
    std::vector<std::uint64_t> keys_;
};

}  // namespace

SeamLevelingResult solveSeamLeveling(const MeshArrays& mesh,
                                     const std::vector<std::uint32_t>& face_patch,
                                     const std::vector<SeamEdge>& seams,
                                     const std::vector<SeamSamples>& samples,
                                     const SeamLevelingOptions& options) {
    if (samples.size() != seams.size() || face_patch.size() != mesh.faces.size()) {
        throw InvalidInput("solveSeamLeveling: " + std::to_string(seams.size()) + " seams but " +
                           std::to_string(samples.size()) + " samples, " +
                           std::to_string(mesh.faces.size()) + " faces but " +
                           std::to_string(face_patch.size()) + " patch ids");
    }
    SeamLevelingResult result;
    result.log_gain = options.space != SeamSpace::kBgr;
    result.corner_correction.assign(mesh.faces.size(),
                                    {Vec3f::Zero(), Vec3f::Zero(), Vec3f::Zero()});
    UnknownIndex index;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        if (face_patch[f] == kNoLabel) continue;
        for (std::uint32_t v : mesh.faces[f]) index.add(face_patch[f], v);
    }
    index.finalize();
    const std::size_t n = index.size();
    result.unknowns = n;
    if (n == 0 || seams.empty()) return result;

    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(n + 8 * seams.size() + 12 * mesh.faces.size());
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), 3);
    auto addDifference = [&](std::size_t i, std::size_t j, double w) {
        triplets.emplace_back(i, i, w);
        triplets.emplace_back(j, j, w);
        triplets.emplace_back(i, j, -w);
        triplets.emplace_back(j, i, -w);
    };
    // Paper Eq. (seam_levelling), first term: (f_l + g_l - f_r - g_r)^2 at both ends of each
    // seam edge. Normal equations: row i gets g_i - g_j = -(f_i - f_j), row j the opposite.
    for (std::size_t k = 0; k < seams.size(); ++k) {
        const SeamEdge& s = seams[k];
        const std::uint32_t pa = face_patch[s.face_a], pb = face_patch[s.face_b];
        const std::pair<std::uint32_t, std::pair<Vec3f, Vec3f>> ends[2] = {
            {s.v0, {samples[k].a_v0, samples[k].b_v0}}, {s.v1, {samples[k].a_v1, samples[k].b_v1}}};
        for (const auto& [v, colors] : ends) {
            const std::size_t i = index.find(pa, v), j = index.find(pb, v);
            const Vec3f d = toSpace(colors.first, options.space) -
                            toSpace(colors.second, options.space);
            if (options.max_log_difference > 0 && options.space != SeamSpace::kBgr) {
                const float dl = toSpace(colors.first, SeamSpace::kLogLuminance)[0] -
                                 toSpace(colors.second, SeamSpace::kLogLuminance)[0];
                if (std::abs(dl) > options.max_log_difference) {
                    ++result.seam_terms_dropped;
                    continue;
                }
            }
            addDifference(i, j, 1.0);
            for (int c = 0; c < 3; ++c) {
                rhs(i, c) -= d[c];
                rhs(j, c) += d[c];
            }
            ++result.seam_terms;
        }
    }
    // Second term: smoothness of g along the edges inside each patch.
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        if (face_patch[f] == kNoLabel) continue;
        for (int e = 0; e < 3; ++e) {
            const std::size_t i = index.find(face_patch[f], mesh.faces[f][e]);
            const std::size_t j = index.find(face_patch[f], mesh.faces[f][(e + 1) % 3]);
            addDifference(i, j, options.smoothness);
        }
    }
    for (std::size_t i = 0; i < n; ++i) triplets.emplace_back(i, i, options.regularizer);
    Eigen::SparseMatrix<double> A(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    A.setFromTriplets(triplets.begin(), triplets.end());
    triplets.clear();
    triplets.shrink_to_fit();

    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
    cg.setMaxIterations(options.max_iterations);
    cg.setTolerance(options.tolerance);
    cg.compute(A);
    Eigen::MatrixXd g(static_cast<Eigen::Index>(n), 3);
    // Log luminance: the three channels are the same problem; solve it once.
    const int channels = options.space == SeamSpace::kLogLuminance ? 1 : 3;
    for (int c = 0; c < channels; ++c) {
        g.col(c) = cg.solve(rhs.col(c));
        result.iterations = std::max(result.iterations, static_cast<int>(cg.iterations()));
    }
    for (int c = channels; c < 3; ++c) g.col(c) = g.col(0);
    result.max_abs_correction = g.size() ? g.cwiseAbs().maxCoeff() : 0.0;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        if (face_patch[f] == kNoLabel) continue;
        for (int k = 0; k < 3; ++k) {
            const std::size_t i = index.find(face_patch[f], mesh.faces[f][k]);
            result.corner_correction[f][k] =
                g.row(static_cast<Eigen::Index>(i)).transpose().cast<float>();
        }
    }
    return result;
}

}  // namespace vdbmap::texture
