// SPDX-License-Identifier: Apache-2.0
#include "pipeline/DatasetReport.h"

#include "vdbmap/io/Dataset.h"
#include "vdbmap/pipeline/Report.h"

namespace vdbmap::detail {

void reportDataset(Report& report, const Dataset& dataset) {
    report.set({"dataset", "format"}, dataset.config().format);
    report.set({"dataset", "path"}, dataset.root().string());
    if (!dataset.config().drive.empty()) report.set({"dataset", "drive"}, dataset.config().drive);
    report.set({"dataset", "poses_file"}, dataset.posesPath().string());
    report.set({"counts", "frames_without_pose"}, dataset.framesWithoutPose());
}

}  // namespace vdbmap::detail
