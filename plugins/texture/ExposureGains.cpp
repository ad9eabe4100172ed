// SPDX-License-Identifier: Apache-2.0
#include "ExposureGains.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "vdbmap/Error.h"

namespace vdbmap::texture {

namespace {

/// The usable observations of the faces used, in CSR form: view, log luminance, base weight.
struct OverlapData {
    std::vector<std::size_t> offsets{0};
    std::vector<std::uint32_t> view;
    std::vector<double> log_l;
    std::vector<double> weight;  // IRLS weight of the current round
};

OverlapData collectOverlaps(const Visibility& vis, const std::vector<ObservationStats>& stats,
                            const ExposureOptions& options, const std::vector<char>* keep) {
    auto usable = [&](std::uint64_t i) {
        if (keep && !(*keep)[i]) return false;
        const ObservationStats& s = stats[i];
        const float l = luminanceBgr(s.mean_bgr);
        return s.pixels >= options.min_pixels && l >= options.min_luminance &&
               l <= options.max_luminance;
    };
    std::vector<std::uint32_t> faces;
    for (std::size_t f = 0; f < vis.numFaces(); ++f) {
        int n = 0;
        for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1] && n < 2; ++i) n += usable(i);
        if (n >= 2) faces.push_back(static_cast<std::uint32_t>(f));
    }
    const std::size_t stride =
        options.max_faces == 0 ? 1 : std::max<std::size_t>(1, (faces.size() + options.max_faces - 1) / options.max_faces);
    OverlapData data;
    for (std::size_t k = 0; k < faces.size(); k += stride) {
        const std::uint32_t f = faces[k];
        for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
            if (!usable(i)) continue;
            data.view.push_back(vis.obs[i].view);
            data.log_l.push_back(std::log(static_cast<double>(luminanceBgr(stats[i].mean_bgr))));
            data.weight.push_back(1.0);
        }
        data.offsets.push_back(data.view.size());
    }
    return data;
}

/// y = S a: the reduced normal matrix, (S a)_v = sum_f w_fv (a_v - abar_f) + prior a_v, with
/// abar_f the w-weighted mean of a over the face's views.
void applyReduced(const OverlapData& d, const Eigen::VectorXd& a, double prior, Eigen::VectorXd& y) {
    y = prior * a;
    for (std::size_t f = 0; f + 1 < d.offsets.size(); ++f) {
        double sw = 0, swa = 0;
        for (std::size_t i = d.offsets[f]; i < d.offsets[f + 1]; ++i) {
            sw += d.weight[i];
            swa += d.weight[i] * a[d.view[i]];
        }
        if (sw <= 0) continue;
        const double mean = swa / sw;
        for (std::size_t i = d.offsets[f]; i < d.offsets[f + 1]; ++i) {
            y[d.view[i]] += d.weight[i] * (a[d.view[i]] - mean);
        }
    }
}

/// One weighted least-squares solve of the reduced system by preconditioned CG.
int solveReduced(const OverlapData& d, std::size_t num_views, const ExposureOptions& options,
                 Eigen::VectorXd& a) {
    const Eigen::Index n = static_cast<Eigen::Index>(num_views);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n), diag = Eigen::VectorXd::Zero(n);
    for (std::size_t f = 0; f + 1 < d.offsets.size(); ++f) {
        double sw = 0, swl = 0;
        for (std::size_t i = d.offsets[f]; i < d.offsets[f + 1]; ++i) {
            sw += d.weight[i];
            swl += d.weight[i] * d.log_l[i];
        }
        if (sw <= 0) continue;
        const double mean = swl / sw;
        for (std::size_t i = d.offsets[f]; i < d.offsets[f + 1]; ++i) {
            rhs[d.view[i]] += d.weight[i] * (d.log_l[i] - mean);
            diag[d.view[i]] += d.weight[i] * (1.0 - d.weight[i] / sw);
        }
    }
    // The prior fixes the constant of each group of views no overlap connects (a null space
    // of S); 1e-9 of the mean diagonal moves a connected solution by a negligible amount.
    const double mean_diag = diag.sum() / std::max<Eigen::Index>(1, (diag.array() > 0).count());
    const double prior = 1e-9 * std::max(mean_diag, 1.0);
    diag.array() += prior;
    Eigen::VectorXd r, z, p, q;
    applyReduced(d, a, prior, q);
    r = rhs - q;
    z = r.cwiseQuotient(diag);
    p = z;
    double rz = r.dot(z);
    const double rhs_norm = std::max(rhs.norm(), 1e-30);
    int it = 0;
    for (; it < options.max_cg_iterations && r.norm() > options.tolerance * rhs_norm; ++it) {
        applyReduced(d, p, prior, q);
        const double alpha = rz / p.dot(q);
        a += alpha * p;
        r -= alpha * q;
        z = r.cwiseQuotient(diag);
        const double rz_next = r.dot(z);
        p = z + (rz_next / rz) * p;
        rz = rz_next;
    }
    return it;
}

/// Huber weights from the residuals e_fv = (l_fv - a_v) - b_f of the current solution.
void reweight(OverlapData& d, const Eigen::VectorXd& a, double huber) {
    std::vector<double> residual(d.view.size());
    for (std::size_t f = 0; f + 1 < d.offsets.size(); ++f) {
        double sw = 0, swd = 0;
        for (std::size_t i = d.offsets[f]; i < d.offsets[f + 1]; ++i) {
            sw += d.weight[i];
            swd += d.weight[i] * (d.log_l[i] - a[d.view[i]]);
        }
        const double b = sw > 0 ? swd / sw : 0.0;
        for (std::size_t i = d.offsets[f]; i < d.offsets[f + 1]; ++i) {
            residual[i] = d.log_l[i] - a[d.view[i]] - b;
        }
    }
    for (std::size_t i = 0; i < residual.size(); ++i) {
        const double e = std::abs(residual[i]);
        d.weight[i] = e <= huber ? 1.0 : huber / e;
    }
}

}  // namespace

ExposureResult estimateExposureGains(const Visibility& vis,
                                     const std::vector<ObservationStats>& stats,
                                     std::size_t num_views, const ExposureOptions& options,
                                     const std::vector<char>* keep) {
    if (stats.size() != vis.obs.size() || (keep && keep->size() != vis.obs.size())) {
        throw InvalidInput("estimateExposureGains: " + std::to_string(vis.obs.size()) +
                           " observations but " + std::to_string(stats.size()) + " statistics");
    }
    ExposureResult result;
    result.gain.assign(num_views, 1.0);
    OverlapData data = collectOverlaps(vis, stats, options, keep);
    result.faces_used = data.offsets.size() - 1;
    result.observations_used = data.view.size();
    std::vector<char> used(num_views, 0);
    for (std::uint32_t v : data.view) {
        if (v < num_views) used[v] = 1;
    }
    for (std::uint32_t v = 0; v < num_views; ++v) {
        if (!used[v]) result.views_without_overlap.push_back(v);
    }
    if (result.faces_used == 0 || num_views == 0) return result;
    for (std::uint32_t v : data.view) {
        if (v >= num_views) {
            throw InvalidInput("estimateExposureGains: observation of view " + std::to_string(v) +
                               " but only " + std::to_string(num_views) + " views");
        }
    }
    Eigen::VectorXd a = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(num_views));
    for (int round = 0; round <= options.irls_iterations; ++round) {
        if (round > 0) reweight(data, a, options.huber_log);
        result.cg_iterations += solveReduced(data, num_views, options, a);
    }
    // Gauge: mean log gain 0 over the views that took part.
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t v = 0; v < num_views; ++v) {
        if (used[v]) {
            sum += a[static_cast<Eigen::Index>(v)];
            ++count;
        }
    }
    const double mean = sum / static_cast<double>(count);
    for (std::size_t v = 0; v < num_views; ++v) {
        if (used[v]) result.gain[v] = std::exp(a[static_cast<Eigen::Index>(v)] - mean);
    }
    return result;
}

void applyExposureGains(const Visibility& vis, const std::vector<double>& gain,
                        std::vector<ObservationStats>& stats) {
    for (std::size_t i = 0; i < vis.obs.size(); ++i) {
        const auto scale = static_cast<float>(1.0 / gain.at(vis.obs[i].view));
        stats[i].mean_bgr *= scale;
        stats[i].quality *= scale;
    }
}

}  // namespace vdbmap::texture
