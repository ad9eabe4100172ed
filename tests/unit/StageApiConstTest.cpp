// SPDX-License-Identifier: Apache-2.0
// The stage API is read-only through const references (issue 13): a plugin holding a const
// Context or a const VoxelMap cannot reach a mutable map, mesh, tile, grid or transform.
// Checked at compile time; the test case only makes the file a test.
#include <catch2/catch.hpp>

#include <memory>
#include <type_traits>
#include <utility>

#include "vdbmap/io/Dataset.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Tiling.h"

using namespace vdbmap;

namespace {

// Context
static_assert(std::is_same_v<decltype(std::declval<const Context&>().map()), const VoxelMap&>);
static_assert(std::is_same_v<decltype(std::declval<const Context&>().mesh()), const TriMesh&>);
static_assert(std::is_same_v<decltype(std::declval<const Context&>().occluderMesh()), const TriMesh&>);
static_assert(std::is_same_v<decltype(std::declval<const Context&>().tile()), const Tile&>);
static_assert(std::is_same_v<decltype(std::declval<const Context&>().dataset()), const Dataset&>);
static_assert(std::is_same_v<decltype(std::declval<const Context&>().mapPtr()),
                             std::shared_ptr<const VoxelMap>>);
static_assert(std::is_same_v<decltype(std::declval<const Context&>().meshPtr()),
                             std::shared_ptr<const TriMesh>>);
// VoxelMap
static_assert(std::is_same_v<decltype(std::declval<const VoxelMap&>().workingTsdf()), TsdfGrid::ConstPtr>);
static_assert(std::is_same_v<decltype(std::declval<const VoxelMap&>().transform()),
                             openvdb::math::Transform::ConstPtr>);
static_assert(std::is_same_v<decltype(std::declval<const VoxelMap&>().compactTsdf()), const CompactTsdf&>);
static_assert(std::is_same_v<decltype(std::declval<const VoxelMap&>().metadata()), const openvdb::MetaMap&>);
static_assert(std::is_same_v<decltype(std::declval<const VoxelMap&>().extraGrids())::mapped_type,
                             openvdb::GridBase::ConstPtr>);

}  // namespace

TEST_CASE("Const accessors of Context and VoxelMap hand out const data only", "[plugin][tiles]") {
    VoxelMap map(0.1);
    map.setExtraGrid("label", openvdb::FloatGrid::create());
    const VoxelMap& view = map;
    CHECK(view.extraGrids().size() == 1);
    CHECK(view.workingTsdf() == map.workingTsdf());
}
