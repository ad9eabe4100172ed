// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/VdbTrees.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace vdbmap {

/// The TSDF lives in ONE OpenVDB tree of 32-bit values (8^3 leaves, the standard 5-4-3
/// configuration): each voxel packs the signed distance D and the weight W of the running
/// average (paper Sec. 4.2) as fixed-point numbers,
///   bits  0..15  D as int16:  D = q_D * sdf_quantum_m,  q_D in [-32767, 32767]
///   bits 16..31  W as uint16: W = q_W * weight_quantum, q_W in [0, 65535].
/// Why: a leaf is 2 KiB instead of the 4 KiB of two float grids, and a voxel update touches
/// one cache line instead of two. The quanta follow from the map's ranges: with an sdf range of
/// 0.30 m the distance resolution is 9.2 um, with a weight range of 100 it is 0.0015, far below
/// the range noise and the weight floor. map.vdb still holds plain float grids (docs/DATA.md),
/// decoded at export (VoxelMap::surfaceGrid, weightGrid).
using TsdfTree = openvdb::UInt32Tree;
using TsdfGrid = openvdb::Grid<TsdfTree>;
using TsdfLeaf = TsdfTree::LeafNodeType;

/// Encodes and decodes packed voxels. Rounding is to nearest (ties to even, the IEEE default
/// mode), without branches or libm calls, so the same inputs give the same bits on every
/// thread and machine.
class TsdfCodec {
public:
    /// Throws InvalidInput unless both ranges are finite and > 0.
    TsdfCodec(float sdf_range_m, float weight_range);

    float sdfRange() const { return sdf_range_m_; }
    float weightRange() const { return weight_range_; }
    float sdfQuantum() const { return sdf_quantum_m_; }
    float weightQuantum() const { return weight_quantum_; }

    /// sdf_m is clamped to [-range, range], weight to [0, range]. A positive weight never
    /// encodes to 0 (0 means unobserved to the mesher).
    std::uint32_t encode(float sdf_m, float weight) const {
        const float qs = clampf(sdf_m * inv_sdf_quantum_, -32767.0f, 32767.0f);
        const float qw = clampf(weight * inv_weight_quantum_, 0.0f, 65535.0f);
        std::uint32_t w = static_cast<std::uint32_t>(roundToInt(qw));
        w |= static_cast<std::uint32_t>(w == 0 && weight > 0.0f);
        return static_cast<std::uint32_t>(static_cast<std::uint16_t>(roundToInt(qs))) | (w << 16);
    }
    float sdf(std::uint32_t value) const {
        return static_cast<float>(static_cast<std::int16_t>(value & 0xFFFFu)) * sdf_quantum_m_;
    }
    float weight(std::uint32_t value) const {
        return static_cast<float>(value >> 16) * weight_quantum_;
    }
    /// The value of unobserved space: D = +sdf range, W = 0.
    std::uint32_t background() const { return encode(sdf_range_m_, 0.0f); }

private:
    /// Branch-free (maxss / minss).
    static float clampf(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }
    /// Round to nearest, ties to even, for |x| < 2^22: adding 1.5 * 2^23 leaves the rounded
    /// integer in the low mantissa bits. Needs IEEE float arithmetic (no -ffast-math).
    static std::int32_t roundToInt(float x) {
        const float t = x + 12582912.0f;
        std::int32_t bits;
        std::memcpy(&bits, &t, sizeof(bits));
        return bits - 0x4B400000;
    }

    float sdf_range_m_;
    float weight_range_;
    float sdf_quantum_m_;
    float weight_quantum_;
    float inv_sdf_quantum_;
    float inv_weight_quantum_;
};

}  // namespace vdbmap
