// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/Version.h"

namespace vdbmap {
const char* versionString() { return VDBMAP_VERSION_STRING; }
}  // namespace vdbmap
