// SPDX-License-Identifier: Apache-2.0
#include "Vignetting.h"

#include <Eigen/Dense>
#include <algorithm>
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

void correctVignetting(cv::Mat& image_f32, const VignettingParams& params, double cu, double cv) {
    if (image_f32.type() != CV_32FC3) {
        throw InvalidInput("correctVignetting: expected a CV_32FC3 image, got type " +
                           std::to_string(image_f32.type()));
    }
    if (params.isIdentity()) return;
    for (int y = 0; y < image_f32.rows; ++y) {
        auto* row = image_f32.ptr<cv::Vec3f>(y);
        for (int x = 0; x < image_f32.cols; ++x) {
            const float g =
                static_cast<float>(vignettingGain(params, vignettingRadius(x, y, cu, cv)));
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

}  // namespace

std::vector<VignettingEstimate> estimateVignetting(const std::vector<VignettingSample>& samples,
                                                   const std::vector<std::uint32_t>& view_camera,
                                                   std::size_t num_cameras) {
    std::vector<VignettingEstimate> result(num_cameras);
    const std::size_t num_views = view_camera.size();
    for (const auto& s : samples) {
        if (s.view >= num_views) {
            throw InvalidInput("estimateVignetting: sample view " + std::to_string(s.view) +
                               " out of range (" + std::to_string(num_views) + " views)");
        }
        if (view_camera[s.view] >= num_cameras) {
            throw InvalidInput("estimateVignetting: camera index out of range");
        }
    }
    // Pair every observation with the first observation of the same face.
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
    const std::size_t n = num_views + 3 * num_cameras;
    std::vector<char> inlier(pairs.size(), 1);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    std::vector<std::size_t> pairs_per_camera(num_cameras, 0);
    for (int round = 0; round < 3; ++round) {
        Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(n, n);
        Eigen::VectorXd Atb = Eigen::VectorXd::Zero(n);
        std::fill(pairs_per_camera.begin(), pairs_per_camera.end(), 0);
        for (std::size_t p = 0; p < pairs.size(); ++p) {
            if (!inlier[p]) continue;
            const Pair& pr = pairs[p];
            // Row: e_i - e_j - h_ci(r_i) + h_cj(r_j) = log L_i - log L_j.
            std::array<std::pair<std::size_t, double>, 8> row;
            const std::size_t ci = num_views + 3 * view_camera[pr.view_i];
            const std::size_t cj = num_views + 3 * view_camera[pr.view_j];
            const double ri2 = double(pr.r_i) * pr.r_i, rj2 = double(pr.r_j) * pr.r_j;
            row[0] = {pr.view_i, 1.0};
            row[1] = {pr.view_j, -1.0};
            row[2] = {ci, -ri2};
            row[3] = {ci + 1, -ri2 * ri2};
            row[4] = {ci + 2, -ri2 * ri2 * ri2};
            row[5] = {cj, rj2};
            row[6] = {cj + 1, rj2 * rj2};
            row[7] = {cj + 2, rj2 * rj2 * rj2};
            for (const auto& [a, va] : row) {
                Atb(a) += va * pr.log_ratio;
                for (const auto& [b, vb] : row) AtA(a, b) += va * vb;
            }
            ++pairs_per_camera[view_camera[pr.view_i]];
            ++pairs_per_camera[view_camera[pr.view_j]];
        }
        // Gauge: the exposures are known up to a constant; sum(e) = 0 fixes it, and a tiny
        // ridge keeps views without pairs (and unobserved cameras) well-posed.
        for (std::size_t a = 0; a < num_views; ++a) {
            for (std::size_t b = 0; b < num_views; ++b) AtA(a, b) += 1.0;
        }
        AtA.diagonal().array() += 1e-9;
        x = AtA.ldlt().solve(Atb);
        if (round == 2) break;
        // Reject occluded / inconsistent pairs: |residual| > 3 robust sigma.
        std::vector<double> abs_res;
        abs_res.reserve(pairs.size());
        std::vector<double> res(pairs.size(), 0.0);
        for (std::size_t p = 0; p < pairs.size(); ++p) {
            const Pair& pr = pairs[p];
            const std::size_t ci = num_views + 3 * view_camera[pr.view_i];
            const std::size_t cj = num_views + 3 * view_camera[pr.view_j];
            const double ri2 = double(pr.r_i) * pr.r_i, rj2 = double(pr.r_j) * pr.r_j;
            const double h_i = x(ci) * ri2 + x(ci + 1) * ri2 * ri2 + x(ci + 2) * ri2 * ri2 * ri2;
            const double h_j = x(cj) * rj2 + x(cj + 1) * rj2 * rj2 + x(cj + 2) * rj2 * rj2 * rj2;
            res[p] = x(pr.view_i) - x(pr.view_j) - h_i + h_j - pr.log_ratio;
            abs_res.push_back(std::abs(res[p]));
        }
        if (abs_res.empty()) break;
        std::nth_element(abs_res.begin(), abs_res.begin() + abs_res.size() / 2, abs_res.end());
        const double sigma = std::max(1.4826 * abs_res[abs_res.size() / 2], 1e-4);
        for (std::size_t p = 0; p < pairs.size(); ++p) inlier[p] = std::abs(res[p]) <= 3.0 * sigma;
    }
    // Final residual per camera.
    std::vector<double> sum_sq(num_cameras, 0.0);
    std::vector<std::size_t> count(num_cameras, 0);
    for (std::size_t p = 0; p < pairs.size(); ++p) {
        if (!inlier[p]) continue;
        const Pair& pr = pairs[p];
        const std::size_t ci = num_views + 3 * view_camera[pr.view_i];
        const std::size_t cj = num_views + 3 * view_camera[pr.view_j];
        const double ri2 = double(pr.r_i) * pr.r_i, rj2 = double(pr.r_j) * pr.r_j;
        const double h_i = x(ci) * ri2 + x(ci + 1) * ri2 * ri2 + x(ci + 2) * ri2 * ri2 * ri2;
        const double h_j = x(cj) * rj2 + x(cj + 1) * rj2 * rj2 + x(cj + 2) * rj2 * rj2 * rj2;
        const double r = x(pr.view_i) - x(pr.view_j) - h_i + h_j - pr.log_ratio;
        for (std::uint32_t cam : {view_camera[pr.view_i], view_camera[pr.view_j]}) {
            sum_sq[cam] += r * r;
            ++count[cam];
        }
    }
    constexpr std::size_t kMinPairs = 30;
    for (std::size_t cam = 0; cam < num_cameras; ++cam) {
        VignettingEstimate& est = result[cam];
        est.pairs_used = pairs_per_camera[cam];
        if (pairs_per_camera[cam] < kMinPairs) continue;
        const std::size_t c = num_views + 3 * cam;
        est.params = polynomialFromLogGain(x(c), x(c + 1), x(c + 2));
        est.rms_log_residual = count[cam] ? std::sqrt(sum_sq[cam] / count[cam]) : 0.0;
    }
    return result;
}

}  // namespace vdbmap::texture
