// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/FreeSpaceVotes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>

namespace vdbmap {

namespace {

/// A VoteScan with its pose in float (points are float; one cast per call, not per point).
struct FloatScan {
    const RangeImage* image;
    Eigen::Matrix3f R_L_W;
    Vec3f t_L_W;
};

/// Adds the votes of `scans` for p_W into `v`.
inline void addVotes(const Vec3f& p_W, const std::vector<FloatScan>& scans, float margin_m,
                     float margin_per_m, float no_return_free_within_m, PointVotes& v) {
    for (const FloatScan& s : scans) {
        const Vec3f p_L = s.R_L_W * p_W + s.t_L_W;
        float d = 0.0f;
        const float bracket = s.image->bracketRange(p_L, d);
        if (bracket == RangeImage::kOutside) continue;  // not in that scan's view: no evidence
        if (bracket == RangeImage::kNoReturn) {
            if (d < no_return_free_within_m) ++v.free;  // nothing anywhere behind p
            continue;
        }
        const float margin = margin_m + margin_per_m * d;
        if (bracket > d + margin) {
            ++v.free;
        } else if (bracket >= d - margin) {
            ++v.hit;
        }
    }
}

std::vector<FloatScan> asFloat(const std::vector<VoteScan>& scans) {
    std::vector<FloatScan> out;
    out.reserve(scans.size());
    for (const VoteScan& s : scans) {
        out.push_back({s.image, s.T_L_W.linear().cast<float>(), s.T_L_W.translation().cast<float>()});
    }
    return out;
}

}  // namespace

PointVotes voteFreeSpace(const Vec3f& p_W, const std::vector<VoteScan>& scans,
                         const FreeSpaceVoteConfig& config) {
    PointVotes v;
    addVotes(p_W, asFloat(scans), static_cast<float>(config.margin_m),
             static_cast<float>(config.margin_per_m), static_cast<float>(config.no_return_free_within_m), v);
    return v;
}

std::vector<std::uint8_t> dynamicByFreeSpace(const std::vector<Vec3f>& points_W,
                                             const std::vector<VoteScan>& first,
                                             const std::vector<VoteScan>& others,
                                             const FreeSpaceVoteConfig& config,
                                             std::size_t* second_pass,
                                             std::vector<PointVotes>* votes) {
    std::vector<std::uint8_t> dynamic(points_W.size(), 0);
    if (votes != nullptr) votes->assign(points_W.size(), PointVotes{});
    std::atomic<std::size_t> asked_all{0};
    if (first.empty() && others.empty()) return dynamic;
    const std::vector<FloatScan> a = asFloat(first), b = asFloat(others);
    const float margin_m = static_cast<float>(config.margin_m);
    const float margin_per_m = static_cast<float>(config.margin_per_m);
    const float no_return_m = static_cast<float>(config.no_return_free_within_m);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_W.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          std::size_t asked = 0;
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              PointVotes v;
                              addVotes(points_W[i], a, margin_m, margin_per_m, no_return_m, v);
                              if (v.free != 0 || a.empty()) {  // else static: no scan saw through it
                                  ++asked;
                                  addVotes(points_W[i], b, margin_m, margin_per_m, no_return_m, v);
                                  dynamic[i] = isDynamic(v, config) ? 1 : 0;
                              }
                              if (votes != nullptr) (*votes)[i] = v;
                          }
                          asked_all += asked;
                      });
    if (second_pass != nullptr) *second_pass = asked_all.load();
    return dynamic;
}

}  // namespace vdbmap
