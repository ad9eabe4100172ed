// SPDX-License-Identifier: Apache-2.0
#include "LidarVotes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <numeric>
#include <string>

#include "vdbmap/Error.h"

namespace vdbmap::semantic {

namespace {

constexpr std::int64_t kCellBias = 1 << 20;  // cells -2^20..2^20-1 per axis

std::int64_t cellOf(float x, float cell_m) {
    return static_cast<std::int64_t>(std::floor(x / cell_m));
}

// 18 bits per axis: cells wrap after 2^18 cells (13 km at 5 cm), far beyond one scan.
std::uint64_t mergeKey(const Vec3f& p, float cell_m) {
    const auto u = [&](float x) {
        return static_cast<std::uint64_t>(cellOf(x, cell_m)) & 0x3FFFFu;
    };
    return (u(p.x()) << 36) | (u(p.y()) << 18) | u(p.z());
}

}  // namespace

float pointTriangleDistance(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const Vec3f ab = b - a, ac = c - a, ap = p - a;
    const float d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return ap.norm();
    const Vec3f bp = p - b;
    const float d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return bp.norm();
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const float v = d1 / (d1 - d3);
        return (p - (a + v * ab)).norm();
    }
    const Vec3f cp = p - c;
    const float d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return cp.norm();
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const float w = d2 / (d2 - d6);
        return (p - (a + w * ac)).norm();
    }
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + w * (c - b))).norm();
    }
    const float denom = 1.0f / (va + vb + vc);
    const float v = vb * denom, w = vc * denom;
    return (p - (a + ab * v + ac * w)).norm();
}

namespace {

std::uint64_t cellKey(std::int64_t x, std::int64_t y, std::int64_t z) {
    const auto u = [](std::int64_t v) {
        return static_cast<std::uint64_t>(std::clamp<std::int64_t>(v + kCellBias, 0,
                                                                   2 * kCellBias - 1));
    };
    return (u(x) << 42) | (u(y) << 21) | u(z);
}

}  // namespace

FaceGrid::FaceGrid(const std::vector<Vec3f>& vertices,
                   const std::vector<std::array<std::uint32_t, 3>>& triangles, float radius_m)
    : vertices_(vertices), triangles_(triangles), radius_m_(radius_m) {
    if (!(radius_m > 0.0f)) throw InvalidInput("FaceGrid: the radius must be > 0");
    const float cell_m = 2.0f * radius_m;
    spheres_.resize(triangles.size(), Eigen::Vector4f::Zero());
    std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
    entries.reserve(triangles.size() * 9);
    for (std::size_t f = 0; f < triangles.size(); ++f) {
        Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::max());
        Vec3f hi = -lo;
        for (const std::uint32_t v : triangles[f]) {
            if (v >= vertices.size()) {
                throw InvalidInput("FaceGrid: face " + std::to_string(f) + " refers to vertex " +
                                   std::to_string(v) + " of " + std::to_string(vertices.size()));
            }
            lo = lo.cwiseMin(vertices[v]);
            hi = hi.cwiseMax(vertices[v]);
        }
        if (!lo.allFinite() || !hi.allFinite()) continue;
        const Vec3f centre = (vertices[triangles[f][0]] + vertices[triangles[f][1]] +
                              vertices[triangles[f][2]]) / 3.0f;
        float bound = 0.0f;
        for (const std::uint32_t v : triangles[f]) bound = std::max(bound, (vertices[v] - centre).norm());
        spheres_[f] << centre, bound + radius_m;
        lo.array() -= radius_m;
        hi.array() += radius_m;
        for (auto x = cellOf(lo.x(), cell_m); x <= cellOf(hi.x(), cell_m); ++x) {
            for (auto y = cellOf(lo.y(), cell_m); y <= cellOf(hi.y(), cell_m); ++y) {
                for (auto z = cellOf(lo.z(), cell_m); z <= cellOf(hi.z(), cell_m); ++z) {
                    entries.emplace_back(cellKey(x, y, z), static_cast<std::uint32_t>(f));
                }
            }
        }
    }
    std::sort(entries.begin(), entries.end());
    cell_faces_.reserve(entries.size());
    for (std::size_t i = 0; i < entries.size(); ++i) {
        if (i == 0 || entries[i].first != entries[i - 1].first) {
            cell_index_.emplace(entries[i].first, static_cast<std::uint32_t>(cell_offsets_.size()));
            cell_offsets_.push_back(i);
        }
        cell_faces_.push_back(entries[i].second);
    }
    cell_offsets_.push_back(entries.size());
}

void FaceGrid::facesWithin(const Vec3f& p, std::vector<std::uint32_t>& faces,
                           std::vector<float>& distances_m) const {
    faces.clear();
    distances_m.clear();
    const float cell_m = 2.0f * radius_m_;
    const auto it = cell_index_.find(
        cellKey(cellOf(p.x(), cell_m), cellOf(p.y(), cell_m), cellOf(p.z(), cell_m)));
    if (it == cell_index_.end()) return;
    for (std::uint64_t k = cell_offsets_[it->second]; k < cell_offsets_[it->second + 1]; ++k) {
        const std::uint32_t f = cell_faces_[k];
        const Eigen::Vector4f& sphere = spheres_[f];
        if ((sphere.head<3>() - p).squaredNorm() >= sphere[3] * sphere[3]) continue;
        const auto& t = triangles_[f];
        const float d = pointTriangleDistance(p, vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]);
        if (d < radius_m_) {
            faces.push_back(f);
            distances_m.push_back(d);
        }
    }
}

LidarVoteAccumulator::LidarVoteAccumulator(
    const std::vector<Vec3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
    std::size_t num_classes, float radius_m, std::size_t batch_points)
    : grid_(vertices, triangles, radius_m > 0.0f ? radius_m : 1.0f),
      batch_points_(std::max<std::size_t>(1, batch_points)),
      num_classes_(num_classes),
      radius_m_(radius_m),
      mass_(triangles.size() * num_classes, 0.0f) {
    if (!(radius_m > 0.0f)) {
        throw InvalidInput("LiDAR votes: the vote radius must be > 0, got " +
                           std::to_string(radius_m));
    }
    if (num_classes == 0) throw InvalidInput("LiDAR votes: no classes");
}

void LidarVoteAccumulator::add(const std::vector<Vec3f>& points_W,
                               const std::vector<std::uint32_t>& classes) {
    if (points_W.size() != classes.size()) {
        throw InvalidInput("LiDAR votes: " + std::to_string(points_W.size()) + " points but " +
                           std::to_string(classes.size()) + " classes");
    }
    for (const std::uint32_t c : classes) {
        if (c != kNoClass && c >= num_classes_) {
            throw InvalidInput("LiDAR votes: class index " + std::to_string(c) +
                               " out of range (" + std::to_string(num_classes_) + " classes)");
        }
    }
    pending_points_.insert(pending_points_.end(), points_W.begin(), points_W.end());
    pending_classes_.insert(pending_classes_.end(), classes.begin(), classes.end());
    if (pending_points_.size() >= batch_points_) flush();
}

void LidarVoteAccumulator::flush() {
    const std::vector<Vec3f>& points_W = pending_points_;
    const std::vector<std::uint32_t>& classes = pending_classes_;
    // 1. Merge the points per (cell of r/2, class): mean position, count as weight.
    const float merge_m = 0.5f * radius_m_;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;  // (cell key, point)
    keyed.reserve(points_W.size());
    for (std::size_t i = 0; i < points_W.size(); ++i) {
        if (classes[i] == kNoClass) {
            ++points_void_;
            continue;
        }
        const Vec3f& p = points_W[i];
        if (!p.allFinite()) continue;
        const std::uint64_t cell = (mergeKey(p, merge_m) << 8) | (classes[i] & 0xFFu);
        keyed.emplace_back(cell, static_cast<std::uint32_t>(i));
    }
    std::sort(keyed.begin(), keyed.end());
    struct Sample {
        Vec3f p;
        std::uint32_t cls;
        std::uint32_t count;
    };
    std::vector<Sample> samples;
    for (std::size_t b = 0; b < keyed.size();) {
        std::size_t e = b;
        Vec3d sum = Vec3d::Zero();
        while (e < keyed.size() && keyed[e].first == keyed[b].first) {
            sum += points_W[keyed[e].second].cast<double>();
            ++e;
        }
        samples.push_back({(sum / static_cast<double>(e - b)).cast<float>(),
                           classes[keyed[b].second], static_cast<std::uint32_t>(e - b)});
        b = e;
    }

    // 2. Each sample's (face, class, weight) triples, in parallel over fixed chunks.
    constexpr std::size_t kChunk = 4096;
    const std::size_t n_chunks = (samples.size() + kChunk - 1) / kChunk;
    struct Triple {
        std::uint32_t face;
        std::uint32_t cls;
        float weight;
    };
    std::vector<std::vector<Triple>> out(n_chunks);
    std::vector<std::size_t> missed(n_chunks, 0);
    const float r2 = radius_m_ * radius_m_;
    tbb::parallel_for(std::size_t(0), n_chunks, [&](std::size_t c) {
        std::vector<std::uint32_t> faces;
        std::vector<float> dist;
        const std::size_t end = std::min(samples.size(), (c + 1) * kChunk);
        for (std::size_t s = c * kChunk; s < end; ++s) {
            grid_.facesWithin(samples[s].p, faces, dist);
            if (faces.empty()) missed[c] += samples[s].count;
            for (std::size_t k = 0; k < faces.size(); ++k) {
                const float w = (1.0f - dist[k] * dist[k] / r2) * static_cast<float>(samples[s].count);
                out[c].push_back({faces[k], samples[s].cls, w});
            }
        }
    });

    // 3. Serial reduction into the dense face x class mass (deterministic order).
    for (std::size_t c = 0; c < n_chunks; ++c) {
        for (const Triple& t : out[c]) mass_[t.face * num_classes_ + t.cls] += t.weight;
        points_without_face_ += missed[c];
    }
    for (const Sample& s : samples) points_voted_ += s.count;
    points_voted_ -= std::accumulate(missed.begin(), missed.end(), std::size_t(0));
    pending_points_.clear();
    pending_classes_.clear();
}

FaceVotes LidarVoteAccumulator::finish() {
    flush();
    FaceVotes votes;
    votes.num_classes = num_classes_;
    const std::size_t n_faces = grid_.numFaces();
    votes.offsets.reserve(n_faces + 1);
    votes.offsets.push_back(0);
    for (std::size_t f = 0; f < n_faces; ++f) {
        for (std::size_t c = 0; c < num_classes_; ++c) {
            const float m = mass_[f * num_classes_ + c];
            if (m > 0.0f) {
                votes.classes.push_back(static_cast<std::uint32_t>(c));
                votes.weights.push_back(m);
            }
        }
        votes.offsets.push_back(votes.classes.size());
    }
    votes.votes = points_voted_;
    votes.void_votes = points_void_;
    return votes;
}

}  // namespace vdbmap::semantic
