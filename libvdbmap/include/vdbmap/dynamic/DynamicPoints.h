// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// The points removed as dynamic: position in the world frame W (metres), the frame (dataset
/// index) and the point's index in that frame's scan file.
struct DynamicPoints {
    std::vector<Vec3f> points_W;
    std::vector<std::uint32_t> frame;
    std::vector<std::uint32_t> index;

    std::size_t size() const { return points_W.size(); }
    void add(const Vec3f& p_W, std::uint32_t f, std::uint32_t i) {
        points_W.push_back(p_W);
        frame.push_back(f);
        index.push_back(i);
    }
    /// Appends `other`'s points.
    void append(const DynamicPoints& other);
};

/// `dynamic_points.ply` as bytes: binary little-endian PLY, one vertex element with the
/// properties float x, float y, float z (W, metres), uint frame, uint index (docs/DATA.md).
std::string dynamicPointsPly(const DynamicPoints& points);
/// Writes it atomically. Throws IoError.
void writeDynamicPointsPly(const std::filesystem::path& path, const DynamicPoints& points);
/// Reads a file of that exact layout. Throws IoError naming the file (another layout, truncated).
DynamicPoints readDynamicPointsPly(const std::filesystem::path& path);

/// The file name of process `rank`'s part of dynamic_points.ply in a distributed run.
std::string dynamicPointsPartName(int rank);
/// Process 0 of a distributed run: merges the parts of ranks 0..processes-1 in `output_dir`
/// into dynamic_points.ply, frames ascending, each frame's points from the lowest rank that has
/// any (every rank that integrated a frame removed the same points), and deletes the parts.
/// Writes nothing if there is no part. Returns the number of points written. Throws IoError.
std::size_t mergeDynamicPointParts(const std::filesystem::path& output_dir, int processes);

}  // namespace vdbmap
