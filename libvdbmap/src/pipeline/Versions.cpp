// SPDX-License-Identifier: Apache-2.0
#include <OpenMesh/Core/System/config.h>
#include <embree3/rtcore_config.h>
#include <oneapi/tbb/version.h>
#include <openvdb/version.h>

#include <opencv2/core/version.hpp>
#include <string>

#include "vdbmap/Version.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"

namespace vdbmap {

void reportVersions(Report& report) {
    report.set({"versions", "vdbmap"}, versionString());
    report.set({"versions", "plugin_abi"}, static_cast<std::int64_t>(VDBMAP_PLUGIN_ABI_VERSION));
    report.set({"versions", "openvdb"}, OPENVDB_LIBRARY_VERSION_STRING);
    report.set({"versions", "openvdb_abi"}, static_cast<std::int64_t>(OPENVDB_ABI_VERSION_NUMBER));
    report.set({"versions", "openmesh"}, std::to_string((OM_VERSION >> 16) & 0xff) + "." +
                                             std::to_string((OM_VERSION >> 8) & 0xff) + "." +
                                             std::to_string(OM_VERSION & 0xff));
    report.set({"versions", "tbb"}, std::string(TBB_runtime_version()));
    report.set({"versions", "opencv"}, CV_VERSION);
    report.set({"versions", "embree"}, RTC_VERSION_STRING);
}

}  // namespace vdbmap
