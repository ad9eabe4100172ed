// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/VdbTrees.h"

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "Commands.h"
#include "vdbmap/Error.h"

namespace {

void printMetadata(const openvdb::MetaMap& meta, const std::string& indent) {
    for (auto it = meta.beginMeta(); it != meta.endMeta(); ++it) {
        std::cout << indent << it->first << " (" << it->second->typeName()
                  << ") = " << it->second->str() << "\n";
    }
}

std::string vec(const openvdb::Vec3d& v) {
    std::ostringstream out;
    out.precision(6);
    out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return out.str();
}

std::string coord(const openvdb::Coord& c) {
    return "(" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " +
           std::to_string(c.z()) + ")";
}

int info(const std::string& file_name) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file_name, ec)) {
        throw vdbmap::IoError(file_name + ": file not found");
    }
    openvdb::io::File file(file_name);
    try {
        file.open(false);
    } catch (const openvdb::Exception& e) {
        throw vdbmap::IoError(file_name + ": not a readable OpenVDB file: " + e.what());
    }
    std::cout << "file: " << file_name << "\n"
              << "  library version: " << file.version() << "\n"
              << "  metadata:\n";
    printMetadata(*file.getMetadata(), "    ");
    openvdb::GridPtrVecPtr grids;
    try {
        grids = file.getGrids();
    } catch (const openvdb::Exception& e) {
        throw vdbmap::IoError(file_name + ": cannot read the grids: " + e.what());
    }
    file.close();
    std::cout << "grids: " << grids->size() << "\n";
    for (const auto& grid : *grids) {
        std::cout << "  " << grid->getName() << "\n"
                  << "    class: " << openvdb::GridBase::gridClassToString(grid->getGridClass())
                  << "\n"
                  << "    value type: " << grid->valueType() << "\n"
                  << "    voxel size: " << vec(grid->voxelSize()) << "\n"
                  << "    active voxels: " << grid->activeVoxelCount() << "\n";
        const openvdb::CoordBBox bbox = grid->evalActiveVoxelBoundingBox();
        if (bbox.empty()) {
            std::cout << "    bounding box: empty\n";
        } else {
            const auto& xform = grid->transform();
            const openvdb::Vec3d lo = xform.indexToWorld(bbox.min().asVec3d() - 0.5);
            const openvdb::Vec3d hi = xform.indexToWorld(bbox.max().asVec3d() + 0.5);
            std::cout << "    bounding box (index): " << coord(bbox.min()) << " .. "
                      << coord(bbox.max()) << "\n"
                      << "    bounding box (world, m): " << vec(lo) << " .. " << vec(hi) << "\n";
        }
        std::cout << "    memory: " << grid->memUsage() << " bytes\n"
                  << "    metadata:\n";
        printMetadata(*grid, "      ");
    }
    return 0;
}

}  // namespace

void addInfoCommand(CLI::App& app, int& exit_code) {
    auto file = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand(
        "info", "Print the grids of a .vdb file: class, type, voxel size, counts, bounds, metadata");
    cmd->add_option("file", *file, "An OpenVDB file (map.vdb)")->required();
    cmd->callback([file, &exit_code] { exit_code = info(*file); });
}
