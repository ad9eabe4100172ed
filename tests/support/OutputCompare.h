// SPDX-License-Identifier: Apache-2.0
// Reading a run's outputs back for comparisons between runs: every file below a folder with
// its bytes, a text file, and the voxels of every float grid of a .vdb file.
#pragma once

#include <openvdb/io/File.h>
#include "vdbmap/map/VdbTrees.h"

#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>

namespace vdbmap::test {

/// Every regular file below `dir`, relative to it, with its bytes.
inline std::map<std::string, std::string> filesBelow(const std::filesystem::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
        if (!entry.is_regular_file()) continue;
        std::ifstream in(entry.path(), std::ios::binary);
        files[std::filesystem::relative(entry.path(), dir).generic_string()] =
            std::string(std::istreambuf_iterator<char>(in), {});
    }
    return files;
}

inline std::string readText(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The active voxels of every float grid of a .vdb file, by grid name. Throws
/// std::runtime_error for a grid of another type.
inline std::map<std::string, std::map<std::array<int, 3>, float>> vdbVoxels(
    const std::filesystem::path& file) {
    openvdb::initialize();
    openvdb::io::File f(file.string());
    f.open();
    const openvdb::GridPtrVecPtr grids = f.getGrids();  // kept alive while iterating
    std::map<std::string, std::map<std::array<int, 3>, float>> out;
    for (const openvdb::GridBase::Ptr& base : *grids) {
        const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!grid) throw std::runtime_error(file.string() + ": grid " + base->getName() + " is not float");
        auto& voxels = out[grid->getName()];
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            voxels[{c.x(), c.y(), c.z()}] = *it;
        }
    }
    return out;
}

}  // namespace vdbmap::test
