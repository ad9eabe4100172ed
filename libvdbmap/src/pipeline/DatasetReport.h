// SPDX-License-Identifier: Apache-2.0
#pragma once

namespace vdbmap {
class Dataset;
class Report;
}  // namespace vdbmap

namespace vdbmap::detail {

/// The dataset's entries of report.json: dataset.format, dataset.path (the folder read),
/// dataset.poses_file (the poses file read: the KITTI layout looks in two places) and
/// counts.frames_without_pose (scans skipped for lack of a pose, KITTI-360).
void reportDataset(Report& report, const Dataset& dataset);

}  // namespace vdbmap::detail
