// SPDX-License-Identifier: Apache-2.0
#include "SemanticVotes.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/map/Layers.h"

namespace vdbmap::semantic {

namespace {

void checkImage(const cv::Mat& image, std::size_t v) {
    if (image.empty() || image.type() != CV_8UC1) {
        throw InvalidInput("semantic votes: label image of view " + std::to_string(v) +
                           (image.empty() ? " is empty"
                                          : " is not 8-bit single channel (OpenCV type " +
                                                std::to_string(image.type()) + ")"));
    }
}

}  // namespace

FaceVotes accumulateVotes(const Visibility& visibility, const std::vector<cv::Mat>& label_images,
                          const LabelSet& labels) {
    return accumulateVotes(
        visibility, label_images.size(), [&](std::size_t v) { return label_images[v]; }, labels,
        label_images.size() + 1);
}

FaceVotes accumulateVotes(const Visibility& visibility, std::size_t num_views,
                          const std::function<cv::Mat(std::size_t)>& load,
                          const LabelSet& labels, std::size_t chunk_views) {
    for (const FaceObservation& obs : visibility.obs) {
        if (obs.view >= num_views) {
            throw InvalidInput("semantic votes: an observation refers to view " +
                               std::to_string(obs.view) + " but there are only " +
                               std::to_string(num_views) + " views");
        }
    }
    chunk_views = std::max<std::size_t>(1, chunk_views);
    const std::size_t num_faces = visibility.numFaces();
    FaceVotes votes;
    votes.num_classes = labels.size();
    // Each observation casts at most one vote, so the face's observation slots bound its
    // distinct classes: fill in place, then compact.
    std::vector<std::uint32_t> slot_class(visibility.obs.size());
    std::vector<float> slot_weight(visibility.obs.size());
    std::vector<std::uint64_t> counts(num_faces + 1, 0);
    // Observations are sorted by view inside a face: a cursor per face walks through them
    // chunk by chunk.
    std::vector<std::uint64_t> cursor(visibility.offsets.begin(),
                                      visibility.offsets.end() - (num_faces > 0 ? 1 : 0));
    struct Counters {
        std::size_t votes = 0, void_votes = 0, unknown = 0;
    };
    tbb::combinable<Counters> counters;
    std::vector<cv::Mat> images;
    for (std::size_t v0 = 0; v0 < num_views; v0 += chunk_views) {
        const std::size_t v1 = std::min(num_views, v0 + chunk_views);
        images.assign(v1 - v0, cv::Mat());
        tbb::parallel_for(std::size_t(0), v1 - v0, [&](std::size_t k) {
            images[k] = load(v0 + k);
            checkImage(images[k], v0 + k);
        });
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, num_faces, 1024),
                          [&](const tbb::blocked_range<std::size_t>& r) {
            Counters& c = counters.local();
            for (std::size_t f = r.begin(); f != r.end(); ++f) {
                const std::uint64_t base = visibility.offsets[f];
                std::uint64_t n = counts[f + 1];
                std::uint64_t& k_obs = cursor[f];
                for (; k_obs < visibility.offsets[f + 1]; ++k_obs) {
                    const FaceObservation& o = visibility.obs[k_obs];
                    if (o.view >= v1) break;
                    const cv::Mat& image = images[o.view - v0];
                    // Paper: only the centre pixel of the triangle, for faces on class edges.
                    const Eigen::Vector2f centre = (o.pixels[0] + o.pixels[1] + o.pixels[2]) / 3.0f;
                    const int u = std::clamp(static_cast<int>(std::lround(centre.x())), 0,
                                             image.cols - 1);
                    const int v = std::clamp(static_cast<int>(std::lround(centre.y())), 0,
                                             image.rows - 1);
                    const std::uint8_t id = image.at<std::uint8_t>(v, u);
                    if (id == kUnknownLabel) {
                        ++c.void_votes;
                        continue;
                    }
                    const int cls = labels.indexOf(id);
                    if (cls < 0) {
                        ++c.unknown;
                        continue;
                    }
                    ++c.votes;
                    // Paper: the vote is the projected size of the face in that image.
                    std::uint64_t k = 0;
                    while (k < n && slot_class[base + k] != static_cast<std::uint32_t>(cls)) ++k;
                    if (k == n) {
                        slot_class[base + n] = static_cast<std::uint32_t>(cls);
                        slot_weight[base + n++] = 0.0f;
                    }
                    slot_weight[base + k] += o.area_px;
                }
                counts[f + 1] = n;
            }
        });
    }
    images.clear();
    counters.combine_each([&](const Counters& c) {
        votes.votes += c.votes;
        votes.void_votes += c.void_votes;
        votes.unknown_id_votes += c.unknown;
    });
    votes.offsets.resize(num_faces + 1);
    std::partial_sum(counts.begin(), counts.end(), votes.offsets.begin());
    votes.classes.resize(votes.offsets.back());
    votes.weights.resize(votes.offsets.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, num_faces, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::pair<std::uint32_t, float>> entries;
        for (std::size_t f = r.begin(); f != r.end(); ++f) {
            const std::uint64_t n = votes.offsets[f + 1] - votes.offsets[f];
            const std::uint64_t src = visibility.offsets[f];
            entries.clear();
            for (std::uint64_t k = 0; k < n; ++k) {
                entries.emplace_back(slot_class[src + k], slot_weight[src + k]);
            }
            std::sort(entries.begin(), entries.end());  // ascending classes
            for (std::uint64_t k = 0; k < n; ++k) {
                votes.classes[votes.offsets[f] + k] = entries[k].first;
                votes.weights[votes.offsets[f] + k] = entries[k].second;
            }
        }
    });
    return votes;
}

}  // namespace vdbmap::semantic
