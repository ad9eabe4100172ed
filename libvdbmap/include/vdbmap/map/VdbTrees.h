// SPDX-License-Identifier: Apache-2.0
#pragma once

/// The OpenVDB trees vdbmap uses, compiled once, in libvdbmap (src/map/trees/*.cpp).
/// Why: openvdb::tree::Tree and openvdb::Grid have virtual functions, so every file that
/// uses a grid would otherwise compile all of them (reading, writing, printing, copying...)
/// for every tree type it touches. Measured under the sanitizer flags (clang 14, -O1, ASan +
/// UBSan): CompactTsdfTest.cpp 57 s -> 22 s. These explicit instantiation declarations stop
/// that; include this header before using any of the trees below (the map headers do).
/// Only Tree and Grid are instantiated: some members of the node classes do not compile for
/// every value type (LeafNode's stream operator for uint32_t buffers), and the nodes have no
/// virtual functions, so a file compiles only the node functions it calls.
#include <openvdb/openvdb.h>

#include <cstdint>

// The tree of the standard 5-4-3 layout or another one, spelled out: an explicit
// instantiation needs the template-id, not an alias.
#define VDBMAP_VDB_TREE(VALUE, N2, N1, N0)                                              \
    openvdb::OPENVDB_VERSION_NAME::tree::Tree<openvdb::OPENVDB_VERSION_NAME::tree::RootNode< \
        openvdb::OPENVDB_VERSION_NAME::tree::InternalNode<                                 \
            openvdb::OPENVDB_VERSION_NAME::tree::InternalNode<                             \
                openvdb::OPENVDB_VERSION_NAME::tree::LeafNode<VALUE, N0>, N1>,             \
            N2>>>

// PREFIX is `extern` for the declarations (here) and empty for the definitions.
#define VDBMAP_VDB_INSTANTIATE(PREFIX, VALUE, N2, N1, N0)         \
    PREFIX template class VDBMAP_VDB_TREE(VALUE, N2, N1, N0);     \
    PREFIX template class openvdb::OPENVDB_VERSION_NAME::Grid<VDBMAP_VDB_TREE(VALUE, N2, N1, N0)>;

VDBMAP_VDB_INSTANTIATE(extern, std::uint32_t, 5, 4, 3)           // TsdfTree (openvdb::UInt32Tree)
VDBMAP_VDB_INSTANTIATE(extern, openvdb::ValueMask, 4, 3, 3)      // CompactTsdf::TopologyTree
VDBMAP_VDB_INSTANTIATE(extern, float, 5, 4, 3)                   // map.vdb's grids (FloatTree)
VDBMAP_VDB_INSTANTIATE(extern, std::int32_t, 5, 4, 3)            // BlockStats' index (Int32Tree)
