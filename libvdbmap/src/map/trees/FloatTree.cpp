// SPDX-License-Identifier: Apache-2.0
// The one compilation of the OpenVDB tree and grid of map.vdb's float grids
// (VdbTrees.h says why).
#include "vdbmap/map/VdbTrees.h"

VDBMAP_VDB_INSTANTIATE(, float, 5, 4, 3)
