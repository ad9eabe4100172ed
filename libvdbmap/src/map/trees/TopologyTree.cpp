// SPDX-License-Identifier: Apache-2.0
// The one compilation of the OpenVDB tree and grid of the topology of CompactTsdf
// (VdbTrees.h says why).
#include "vdbmap/map/VdbTrees.h"

VDBMAP_VDB_INSTANTIATE(, openvdb::ValueMask, 4, 3, 3)
