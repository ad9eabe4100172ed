// SPDX-License-Identifier: Apache-2.0
#include "sim/SimLidarLabels.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <numeric>

#include "sim/SimImaging.h"

namespace vdbmap {

std::uint16_t semanticKittiId(std::uint8_t our_id) {
    // docs/DATA.md ids 0..20 -> SemanticKITTI (semantic-kitti.yaml `labels`).
    static constexpr std::uint16_t kTable[21] = {
        40,  // road
        48,  // sidewalk
        50,  // building
        52,  // wall -> other-structure
        51,  // fence
        80,  // pole
        81,  // traffic light -> traffic-sign
        81,  // traffic sign
        70,  // vegetation
        72,  // terrain
        0,   // sky -> unlabeled
        30,  // person
        31,  // rider -> bicyclist
        10,  // car
        18,  // truck
        13,  // bus
        16,  // train -> on-rails
        15,  // motorcycle
        11,  // bicycle
        60,  // lane marking
        99,  // other object
    };
    return our_id < 21 ? kTable[our_id] : 0;
}

LidarLabels simulateLidarLabels(const LidarScan& scan, const LidarModel& model,
                                const std::vector<std::uint8_t>& face_labels,
                                const std::vector<std::uint8_t>& scene_classes,
                                const SimLidarLabelOptions& options, std::mt19937_64& rng) {
    const std::size_t n = scan.faces.size();
    std::vector<std::uint8_t> ours(n);
    for (std::size_t i = 0; i < n; ++i) ours[i] = face_labels.at(scan.faces[i]);

    // Boundary noise on the range image: rows = beams by elevation, cols = azimuth steps.
    if (options.boundary_px > 0 && n > 0) {
        const std::size_t n_beams = model.numBeams();
        const std::size_t n_az = model.numAzimuths();
        std::vector<int> row_of_beam(n_beams);
        std::vector<int> order(n_beams);
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
            return model.elevations_deg[a] > model.elevations_deg[b];
        });
        for (std::size_t r = 0; r < n_beams; ++r) row_of_beam[order[r]] = static_cast<int>(r);
        cv::Mat image(static_cast<int>(n_beams), static_cast<int>(n_az), CV_8UC1, cv::Scalar(255));
        const auto pixel = [&](std::uint32_t ray) {
            return cv::Point(static_cast<int>(ray / n_beams), row_of_beam[ray % n_beams]);
        };
        for (std::size_t i = 0; i < n; ++i) image.at<std::uint8_t>(pixel(scan.rays[i])) = ours[i];
        ImagingOptions noise;
        noise.label_noise_px = options.boundary_px;
        addLabelNoise(image, noise, rng);
        for (std::size_t i = 0; i < n; ++i) ours[i] = image.at<std::uint8_t>(pixel(scan.rays[i]));
    }

    // Random flips to another class of the scene.
    if (options.flip_rate > 0.0 && scene_classes.size() > 1) {
        std::uniform_real_distribution<double> uniform(0.0, 1.0);
        std::uniform_int_distribution<std::size_t> pick(0, scene_classes.size() - 2);
        for (std::size_t i = 0; i < n; ++i) {
            const bool flip = uniform(rng) < options.flip_rate;
            const std::size_t k = pick(rng);
            if (!flip || ours[i] == 255) continue;
            // The k-th scene class other than the true one.
            const auto self = std::find(scene_classes.begin(), scene_classes.end(), ours[i]);
            const std::size_t skip = static_cast<std::size_t>(self - scene_classes.begin());
            ours[i] = scene_classes[k < skip ? k : k + 1];
        }
    }

    LidarLabels labels;
    labels.raw.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        labels.raw[i] = options.semantickitti_ids ? semanticKittiId(ours[i]) : ours[i];
    }
    return labels;
}

}  // namespace vdbmap
