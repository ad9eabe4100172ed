// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>

#include "vdbmap/core/Types.h"

namespace vdbmap {

/// Reads a KITTI velodyne scan: float32 little-endian x y z reflectance per point, in the
/// sensor frame. Throws IoError naming the file if it is missing or its size is not a multiple
/// of 16 bytes (a truncated file). An empty file is an empty cloud.
PointCloud readBin(const std::filesystem::path& path);
/// Same into `cloud`, reusing its storage (a reader of many scans allocates once). On a throw
/// `cloud` holds no scan.
void readBin(const std::filesystem::path& path, PointCloud& cloud);

/// Reads a PCD file (v0.5-0.7 header: VERSION FIELDS SIZE TYPE COUNT WIDTH HEIGHT VIEWPOINT
/// POINTS DATA) with DATA ascii, binary or binary_compressed (LZF, field-major). Fields x y z
/// are required, "intensity" (or "i", "reflectance", "remission") is optional; fields may come
/// in any order with any of the types F4 F8 U1 U2 U4 U8 I1 I2 I4 I8. Points are returned as
/// stored (NaN points of organised clouds included; Dataset::loadScan drops them). Throws
/// IoError naming the file, and for a corrupt header the line number and text.
PointCloud readPcd(const std::filesystem::path& path);

/// Reads the "vertex" element of a PLY (ascii, binary little or big endian): x y z, plus an
/// intensity from a property named "intensity", "scalar_intensity", "reflectance" or
/// "scalar_Intensity" if present. Throws IoError naming the file.
PointCloud readPlyPoints(const std::filesystem::path& path);

/// Dispatches on the extension (.bin, .pcd, .ply; case-insensitive). Throws IoError for any
/// other extension.
PointCloud readPointCloud(const std::filesystem::path& path);
/// Same into `cloud` (readBin reuses its storage).
void readPointCloud(const std::filesystem::path& path, PointCloud& cloud);

/// True if `path` has an extension readPointCloud understands.
bool isPointCloudFile(const std::filesystem::path& path);

/// PCD DATA encodings.
enum class PcdEncoding { Ascii, Binary, BinaryCompressed };

/// Writes a KITTI .bin (intensity 0 where the cloud has none), atomically. Throws IoError.
void writeBin(const std::filesystem::path& path, const PointCloud& cloud);
/// Writes a PCD v0.7 with fields x y z intensity (F4), atomically. ascii values are written
/// in shortest round-trip form, so every encoding reads back bit-identical. Throws IoError.
void writePcd(const std::filesystem::path& path, const PointCloud& cloud,
              PcdEncoding encoding = PcdEncoding::Binary);
/// Writes a binary little-endian PLY point cloud (vertex x y z intensity as float),
/// atomically. Throws IoError.
void writePlyPoints(const std::filesystem::path& path, const PointCloud& cloud);

}  // namespace vdbmap
