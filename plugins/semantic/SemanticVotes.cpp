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

struct VoteCounters {
    std::size_t votes = 0, void_votes = 0, unknown = 0;
};

// The class index the centre pixel of an observation votes for, or -1 (void or an id outside
// the label set, counted). Paper: only the centre pixel of the triangle, for faces on class
// edges.
int centreClass(const FaceObservation& o, const cv::Mat& image, const LabelSet& labels,
                VoteCounters& c) {
    const Eigen::Vector2f centre = (o.pixels[0] + o.pixels[1] + o.pixels[2]) / 3.0f;
    const int u = std::clamp(static_cast<int>(std::lround(centre.x())), 0, image.cols - 1);
    const int v = std::clamp(static_cast<int>(std::lround(centre.y())), 0, image.rows - 1);
    const std::uint8_t id = image.at<std::uint8_t>(v, u);
    if (id == kUnknownLabel) {
        ++c.void_votes;
        return -1;
    }
    const int cls = labels.indexOf(id);
    if (cls < 0) {
        ++c.unknown;
        return -1;
    }
    ++c.votes;
    return cls;
}

// Per-face vote slots, filled chunk of views by chunk. Each observation casts at most one
// vote, so the face's observation slots bound its distinct classes: fill in place, then
// compact.
class VoteSlots {
public:
    explicit VoteSlots(const Visibility& visibility)
        : vis_(visibility),
          slot_class_(visibility.obs.size()),
          slot_weight_(visibility.obs.size()),
          counts_(visibility.numFaces() + 1, 0),
          // Observations are sorted by view inside a face: a cursor per face walks through
          // them chunk by chunk.
          cursor_(visibility.offsets.begin(),
                  visibility.offsets.end() - (visibility.numFaces() > 0 ? 1 : 0)) {}

    // The votes of views [v0, v1) (images[k] is view v0 + k), parallel over faces.
    void addChunk(const std::vector<cv::Mat>& images, std::size_t v0, std::size_t v1,
                  const LabelSet& labels, tbb::combinable<VoteCounters>& counters) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vis_.numFaces(), 1024),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              VoteCounters& c = counters.local();
                              for (std::size_t f = r.begin(); f != r.end(); ++f) {
                                  addFace(f, images, v0, v1, labels, c);
                              }
                          });
    }

    // The slots as CSR votes, classes ascending inside a face.
    FaceVotes compact(std::size_t num_classes) const {
        const std::size_t num_faces = vis_.numFaces();
        FaceVotes votes;
        votes.num_classes = num_classes;
        votes.offsets.resize(num_faces + 1);
        std::partial_sum(counts_.begin(), counts_.end(), votes.offsets.begin());
        votes.classes.resize(votes.offsets.back());
        votes.weights.resize(votes.offsets.back());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, num_faces, 4096),
                          [&](const tbb::blocked_range<std::size_t>& r) {
            std::vector<std::pair<std::uint32_t, float>> entries;
            for (std::size_t f = r.begin(); f != r.end(); ++f) {
                const std::uint64_t n = votes.offsets[f + 1] - votes.offsets[f];
                const std::uint64_t src = vis_.offsets[f];
                entries.clear();
                for (std::uint64_t k = 0; k < n; ++k) {
                    entries.emplace_back(slot_class_[src + k], slot_weight_[src + k]);
                }
                std::sort(entries.begin(), entries.end());
                for (std::uint64_t k = 0; k < n; ++k) {
                    votes.classes[votes.offsets[f] + k] = entries[k].first;
                    votes.weights[votes.offsets[f] + k] = entries[k].second;
                }
            }
        });
        return votes;
    }

private:
    void addFace(std::size_t f, const std::vector<cv::Mat>& images, std::size_t v0,
                 std::size_t v1, const LabelSet& labels, VoteCounters& c) {
        const std::uint64_t base = vis_.offsets[f];
        std::uint64_t n = counts_[f + 1];
        std::uint64_t& k_obs = cursor_[f];
        for (; k_obs < vis_.offsets[f + 1]; ++k_obs) {
            const FaceObservation& o = vis_.obs[k_obs];
            if (o.view >= v1) break;
            const int cls = centreClass(o, images[o.view - v0], labels, c);
            if (cls < 0) continue;
            // Paper: the vote is the projected size of the face in that image.
            std::uint64_t k = 0;
            while (k < n && slot_class_[base + k] != static_cast<std::uint32_t>(cls)) ++k;
            if (k == n) {
                slot_class_[base + n] = static_cast<std::uint32_t>(cls);
                slot_weight_[base + n++] = 0.0f;
            }
            slot_weight_[base + k] += o.area_px;
        }
        counts_[f + 1] = n;
    }

    const Visibility& vis_;
    std::vector<std::uint32_t> slot_class_;
    std::vector<float> slot_weight_;
    std::vector<std::uint64_t> counts_;  // [f + 1]: slots used by face f
    std::vector<std::uint64_t> cursor_;  // [f]: next observation of face f
};

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
    VoteSlots slots(visibility);
    tbb::combinable<VoteCounters> counters;
    std::vector<cv::Mat> images;
    for (std::size_t v0 = 0; v0 < num_views; v0 += chunk_views) {
        const std::size_t v1 = std::min(num_views, v0 + chunk_views);
        images.assign(v1 - v0, cv::Mat());
        tbb::parallel_for(std::size_t(0), v1 - v0, [&](std::size_t k) {
            images[k] = load(v0 + k);
            checkImage(images[k], v0 + k);
        });
        slots.addChunk(images, v0, v1, labels, counters);
    }
    images.clear();
    FaceVotes votes = slots.compact(labels.size());
    counters.combine_each([&](const VoteCounters& c) {
        votes.votes += c.votes;
        votes.void_votes += c.void_votes;
        votes.unknown_id_votes += c.unknown;
    });
    return votes;
}

}  // namespace vdbmap::semantic
