// SPDX-License-Identifier: Apache-2.0
// The one compilation of the OpenVDB tree and grid of the block index of BlockStats
// (VdbTrees.h says why).
#include "vdbmap/map/VdbTrees.h"

VDBMAP_VDB_INSTANTIATE(, std::int32_t, 5, 4, 3)
