// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/FreeSpaceVotes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <limits>

namespace vdbmap {

namespace {

/// A VoteScan with its pose in float (points are float; one cast per call, not per point).
struct FloatScan {
    const RangeImage* image;
    Eigen::Matrix3f R_L_W;
    Vec3f t_L_W;
};

/// The margins of a vote, in float (FreeSpaceVoteConfig).
struct Margins {
    float margin_m, margin_per_m, no_return_free_within_m, thin_m, thin_per_m;
    explicit Margins(const FreeSpaceVoteConfig& c)
        : margin_m(static_cast<float>(c.margin_m)), margin_per_m(static_cast<float>(c.margin_per_m)),
          no_return_free_within_m(static_cast<float>(c.no_return_free_within_m)),
          thin_m(c.thin_margin_m > 0.0 ? static_cast<float>(c.thin_margin_m) : std::numeric_limits<float>::max()),
          thin_per_m(static_cast<float>(c.thin_margin_per_m)) {}
};

/// One scan's vote for a point at range d whose pixel's bracket range is `bracket`.
inline void vote(float bracket, float d, const Margins& m, PointVotes& v) {
    if (bracket == RangeImage::kNoReturn) {
        if (d < m.no_return_free_within_m) ++v.free;  // nothing anywhere behind p
        return;
    }
    const float margin = m.margin_m + m.margin_per_m * d;
    if (bracket > d + margin) {
        ++v.free;
    } else if (bracket >= d - margin) {
        ++v.hit;
        if (bracket > d + m.thin_m + m.thin_per_m * d) ++v.thin;
    }
}

/// Adds the votes of `scans` for p_W into `v`.
inline void addVotes(const Vec3f& p_W, const std::vector<FloatScan>& scans, const Margins& m, PointVotes& v) {
    for (const FloatScan& s : scans) {
        const Vec3f p_L = s.R_L_W * p_W + s.t_L_W;
        float d = 0.0f;
        const float bracket = s.image->bracketRange(p_L, d);
        if (bracket == RangeImage::kOutside) continue;  // not in that scan's view: no evidence
        vote(bracket, d, m, v);
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
    addVotes(p_W, asFloat(scans), Margins(config), v);
    return v;
}

namespace {

/// Points handled together by the look-up kernel (their coordinates in one scan's frame fit in
/// the first-level cache).
constexpr std::size_t kBlock = 256;

/// A block of points in W as coordinate arrays, and the scratch of the look-ups.
struct VoteBlock {
    std::size_t n = 0;
    float x[kBlock], y[kBlock], z[kBlock];     ///< W
    float lx[kBlock], ly[kBlock], lz[kBlock];  ///< one scan's L
    float range[kBlock];
    std::int32_t pixel[kBlock];
};

/// addVotes for a block: the same votes, point by point, as addVotes gives each point (the
/// same float arithmetic: p_L = R p + t row by row, then RangeImage::pixelsOf).
void addVotesBlock(VoteBlock& b, const std::vector<FloatScan>& scans, const Margins& m, PointVotes* v) {
    for (const FloatScan& s : scans) {
        const Eigen::Matrix3f& R = s.R_L_W;
        const Vec3f& t = s.t_L_W;
        for (std::size_t i = 0; i < b.n; ++i) {
            b.lx[i] = R(0, 0) * b.x[i] + R(0, 1) * b.y[i] + R(0, 2) * b.z[i] + t.x();
            b.ly[i] = R(1, 0) * b.x[i] + R(1, 1) * b.y[i] + R(1, 2) * b.z[i] + t.y();
            b.lz[i] = R(2, 0) * b.x[i] + R(2, 1) * b.y[i] + R(2, 2) * b.z[i] + t.z();
        }
        s.image->pixelsOf(b.lx, b.ly, b.lz, b.n, b.pixel, b.range);
        for (std::size_t i = 0; i < b.n; ++i) {
            if (b.pixel[i] < 0) continue;  // not in that scan's view: no evidence
            vote(s.image->bracketAt(b.pixel[i]), b.range[i], m, v[i]);
        }
    }
}

}  // namespace

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
    const Margins margins(config);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_W.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          std::size_t asked = 0;
                          VoteBlock block, again;
                          PointVotes v[kBlock], v_again[kBlock];
                          std::size_t again_of[kBlock];
                          for (std::size_t begin = range.begin(); begin < range.end(); begin += kBlock) {
                              // The first scans for every point of the block.
                              block.n = std::min(kBlock, range.end() - begin);
                              for (std::size_t k = 0; k < block.n; ++k) {
                                  const Vec3f& p = points_W[begin + k];
                                  block.x[k] = p.x(), block.y[k] = p.y(), block.z[k] = p.z();
                                  v[k] = PointVotes{};
                              }
                              addVotesBlock(block, a, margins, v);
                              // The others for those some first scan saw through (else static).
                              again.n = 0;
                              for (std::size_t k = 0; k < block.n; ++k) {
                                  if (!needsSecondPass(v[k], config) && !a.empty()) continue;
                                  again.x[again.n] = block.x[k], again.y[again.n] = block.y[k];
                                  again.z[again.n] = block.z[k];
                                  v_again[again.n] = v[k];
                                  again_of[again.n++] = k;
                              }
                              asked += again.n;
                              addVotesBlock(again, b, margins, v_again);
                              for (std::size_t j = 0; j < again.n; ++j) {
                                  v[again_of[j]] = v_again[j];
                                  dynamic[begin + again_of[j]] = isDynamic(v_again[j], config) ? 1 : 0;
                              }
                              if (votes != nullptr) {
                                  std::copy(v, v + block.n, votes->begin() + static_cast<std::ptrdiff_t>(begin));
                              }
                          }
                          asked_all += asked;
                      });
    if (second_pass != nullptr) *second_pass = asked_all.load();
    return dynamic;
}

}  // namespace vdbmap
