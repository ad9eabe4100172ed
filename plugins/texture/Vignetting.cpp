// SPDX-License-Identifier: Apache-2.0
#include "Vignetting.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "vdbmap/Error.h"

namespace vdbmap::texture {

double vignettingRadius(double u, double v, double cu, double cv) {
    // Paper: r = sqrt((u - cu)^2 + (v - cv)^2) / sqrt(cu^2 + cv^2).
    const double norm = std::sqrt(cu * cu + cv * cv);
    if (norm <= 0) return 0.0;
    return std::sqrt((u - cu) * (u - cu) + (v - cv) * (v - cv)) / norm;
}

double vignettingGain(const VignettingParams& params, double r) {
    const double r2 = r * r;
    // Paper: g(r) = 1 + a r^2 + b r^4 + c r^6.
    return 1.0 + r2 * (params.a + r2 * (params.b + r2 * params.c));
}

void correctVignetting(cv::Mat& image_f32, const VignettingParams& params, double cu, double cv,
                       cv::Point origin) {
    if (image_f32.type() != CV_32FC3) {
        throw InvalidInput("correctVignetting: expected a CV_32FC3 image, got type " +
                           std::to_string(image_f32.type()));
    }
    if (params.isIdentity()) return;
    for (int y = 0; y < image_f32.rows; ++y) {
        auto* row = image_f32.ptr<cv::Vec3f>(y);
        for (int x = 0; x < image_f32.cols; ++x) {
            const float g =
                static_cast<float>(vignettingGain(params, vignettingRadius(x + origin.x, y + origin.y, cu, cv)));
            row[x] *= g;  // Paper: I'(u, v) = g(r) * I(u, v)
        }
    }
}

namespace {

struct Pair {
    std::uint32_t view_i, view_j;
    float r_i, r_j;
    double log_ratio;
};

/// Fits (a, b, c) of 1 + a r^2 + b r^4 + c r^6 to exp(h(r)) on r in [0, 1].
VignettingParams polynomialFromLogGain(double alpha, double beta, double gamma) {
    constexpr int kSamples = 101;
    Eigen::MatrixXd A(kSamples, 3);
    Eigen::VectorXd y(kSamples);
    for (int k = 0; k < kSamples; ++k) {
        const double r2 = (k / double(kSamples - 1)) * (k / double(kSamples - 1));
        A(k, 0) = r2;
        A(k, 1) = r2 * r2;
        A(k, 2) = r2 * r2 * r2;
        y(k) = std::exp(alpha * r2 + beta * r2 * r2 + gamma * r2 * r2 * r2) - 1.0;
    }
    const Eigen::Vector3d p = A.colPivHouseholderQr().solve(y);
    return {p(0), p(1), p(2)};
}

// The unknowns x of the joint fit: an exposure e_v per view, then (alpha, beta, gamma) of the
// log-gain h_c(r) = alpha r^2 + beta r^4 + gamma r^6 per camera.
struct VignettingUnknowns {
    const std::vector<std::uint32_t>& view_camera;
    std::size_t num_views() const { return view_camera.size(); }
    std::size_t size(std::size_t num_cameras) const { return num_views() + 3 * num_cameras; }
    std::size_t cameraOffset(std::uint32_t view) const { return num_views() + 3 * view_camera[view]; }

    // One pair's row of the linear system:
    // e_i - e_j - h_ci(r_i) + h_cj(r_j) = log L_i - log L_j.
    std::array<std::pair<std::size_t, double>, 8> row(const Pair& pr) const {
        const std::size_t ci = cameraOffset(pr.view_i), cj = cameraOffset(pr.view_j);
        const double ri2 = double(pr.r_i) * pr.r_i, rj2 = double(pr.r_j) * pr.r_j;
        return {{{pr.view_i, 1.0},
                 {pr.view_j, -1.0},
                 {ci, -ri2},
                 {ci + 1, -ri2 * ri2},
                 {ci + 2, -ri2 * ri2 * ri2},
                 {cj, rj2},
                 {cj + 1, rj2 * rj2},
                 {cj + 2, rj2 * rj2 * rj2}}};
    }

    double residual(const Pair& pr, const Eigen::VectorXd& x) const {
        double r = -pr.log_ratio;
        for (const auto& [a, v] : row(pr)) r += v * x(a);
        return r;
    }
};

void checkSamples(const std::vector<VignettingSample>& samples,
                  const std::vector<std::uint32_t>& view_camera, std::size_t num_cameras) {
    for (const auto& s : samples) {
        if (s.view >= view_camera.size()) {
            throw InvalidInput("estimateVignetting: sample view " + std::to_string(s.view) +
                               " out of range (" + std::to_string(view_camera.size()) + " views)");
        }
        if (view_camera[s.view] >= num_cameras) {
            throw InvalidInput("estimateVignetting: camera index out of range");
        }
    }
}

// Every observation paired with the first observation of the same face (samples come sorted
// by face).
std::vector<Pair> pairObservations(const std::vector<VignettingSample>& samples) {
    std::vector<Pair> pairs;
    for (std::size_t begin = 0; begin < samples.size();) {
        std::size_t end = begin + 1;
        while (end < samples.size() && samples[end].face == samples[begin].face) ++end;
        const VignettingSample& ref = samples[begin];
        for (std::size_t k = begin + 1; k < end; ++k) {
            const VignettingSample& s = samples[k];
            if (s.view == ref.view || s.luminance <= 0 || ref.luminance <= 0) continue;
            pairs.push_back({s.view, ref.view, s.radius, ref.radius,
                             std::log(double(s.luminance)) - std::log(double(ref.luminance))});
        }
        begin = end;
    }
    return pairs;
}

// Least squares over the inlier pairs (normal equations). Gauge: the exposures are known up to
// a constant; sum(e) = 0 fixes it, and a tiny ridge keeps views without pairs (and unobserved
// cameras) well-posed. Counts the inlier pairs per camera.
Eigen::VectorXd solveInliers(const std::vector<Pair>& pairs, const std::vector<char>& inlier,
                             const VignettingUnknowns& u, std::size_t num_cameras,
                             std::vector<std::size_t>& pairs_per_camera) {
    const std::size_t n = u.size(num_cameras);
    Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd Atb = Eigen::VectorXd::Zero(n);
    pairs_per_camera.assign(num_cameras, 0);
    for (std::size_t p = 0; p < pairs.size(); ++p) {
        if (!inlier[p]) continue;
        const auto row = u.row(pairs[p]);
        for (const auto& [a, va] : row) {
            Atb(a) += va * pairs[p].log_ratio;
            for (const auto& [b, vb] : row) AtA(a, b) += va * vb;
        }
        ++pairs_per_camera[u.view_camera[pairs[p].view_i]];
        ++pairs_per_camera[u.view_camera[pairs[p].view_j]];
    }
    AtA.topLeftCorner(u.num_views(), u.num_views()).array() += 1.0;
    AtA.diagonal().array() += 1e-9;
    return AtA.ldlt().solve(Atb);
}

// Rejects occluded / inconsistent pairs: |residual| > 3 robust sigma. False if no pair is left
// to judge.
bool rejectOutliers(const std::vector<Pair>& pairs, const VignettingUnknowns& u,
                    const Eigen::VectorXd& x, std::vector<char>& inlier) {
    if (pairs.empty()) return false;
    std::vector<double> res(pairs.size());
    for (std::size_t p = 0; p < pairs.size(); ++p) res[p] = u.residual(pairs[p], x);
    std::vector<double> abs_res(res.size());
    std::transform(res.begin(), res.end(), abs_res.begin(), [](double r) { return std::abs(r); });
    std::nth_element(abs_res.begin(), abs_res.begin() + abs_res.size() / 2, abs_res.end());
    const double sigma = std::max(1.4826 * abs_res[abs_res.size() / 2], 1e-4);
    for (std::size_t p = 0; p < pairs.size(); ++p) inlier[p] = std::abs(res[p]) <= 3.0 * sigma;
    return true;
}

}  // namespace

std::vector<VignettingEstimate> estimateVignetting(const std::vector<VignettingSample>& samples,
                                                   const std::vector<std::uint32_t>& view_camera,
                                                   std::size_t num_cameras) {
    checkSamples(samples, view_camera, num_cameras);
    const std::vector<Pair> pairs = pairObservations(samples);
    const VignettingUnknowns u{view_camera};
    std::vector<char> inlier(pairs.size(), 1);
    std::vector<std::size_t> pairs_per_camera;
    Eigen::VectorXd x;
    for (int round = 0; round < 3; ++round) {
        x = solveInliers(pairs, inlier, u, num_cameras, pairs_per_camera);
        if (round == 2 || !rejectOutliers(pairs, u, x, inlier)) break;
    }
    // Final residual per camera.
    std::vector<double> sum_sq(num_cameras, 0.0);
    std::vector<std::size_t> count(num_cameras, 0);
    for (std::size_t p = 0; p < pairs.size(); ++p) {
        if (!inlier[p]) continue;
        const double r = u.residual(pairs[p], x);
        for (std::uint32_t cam : {view_camera[pairs[p].view_i], view_camera[pairs[p].view_j]}) {
            sum_sq[cam] += r * r;
            ++count[cam];
        }
    }
    constexpr std::size_t kMinPairs = 30;
    std::vector<VignettingEstimate> result(num_cameras);
    for (std::size_t cam = 0; cam < num_cameras; ++cam) {
        VignettingEstimate& est = result[cam];
        est.pairs_used = pairs_per_camera[cam];
        if (pairs_per_camera[cam] < kMinPairs) continue;
        const std::size_t c = view_camera.size() + 3 * cam;
        est.params = polynomialFromLogGain(x(c), x(c + 1), x(c + 2));
        est.rms_log_residual = count[cam] ? std::sqrt(sum_sq[cam] / count[cam]) : 0.0;
    }
    return result;
}

}  // namespace vdbmap::texture
