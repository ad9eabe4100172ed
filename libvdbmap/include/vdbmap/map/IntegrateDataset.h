// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "vdbmap/io/Dataset.h"

namespace vdbmap {

class AtsdfIntegrator;

/// What integrateDataset did (its integration counts are in the integrator's totals()).
struct DatasetIntegration {
    ScanReadStats read;      ///< summed over the scans
    double seconds = 0.0;    ///< wall time of the whole loop, reading included
    double read_wait_s = 0.0;  ///< of which waiting for a scan that was not read yet
    double on_scan_s = 0.0;    ///< of which in `on_scan` (not integration: progress, tiles)
};

/// The scan loop of integrate.atsdf: the frames `frames` of `dataset` (ascending indices) in
/// order, in the LiDAR frame with its pose T_W_L. With `read_ahead`, the next scan is read and
/// filtered while one is integrated (reading overlaps integration and `on_scan`; at most one
/// scan in flight): as a task of the TBB threads if there are several, else on a thread of its
/// own. Calls `on_scan(frame)` after each scan (progress, streamed tiles). A read error is
/// rethrown as thrown by Dataset::loadScan, after the scans before it were integrated. Throws
/// std::out_of_range for a frame past the dataset.
DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::vector<std::size_t>& frames,
                                    const std::function<void(std::size_t)>& on_scan = {},
                                    bool read_ahead = true);
/// Called on each scan after it is read and range-filtered, before it is integrated: may drop
/// points of `cloud_L` (LiDAR frame; keep intensity aligned). `index` holds each point's index
/// in the scan file and `points_in_file` that file's point count. It runs in the read-ahead
/// task, one scan at a time, frames in the order integrated.
using ScanFilter = std::function<void(std::size_t frame, PointCloud& cloud_L,
                                      const std::vector<std::uint32_t>& index,
                                      std::size_t points_in_file)>;
/// The same, with `filter` applied to each scan (empty: none).
DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::vector<std::size_t>& frames,
                                    const std::function<void(std::size_t)>& on_scan,
                                    const ScanFilter& filter, bool read_ahead = true);
/// The same with a second filter, `late_filter`, applied after the scan's rings are estimated
/// (RingSpacing, for the integrator's grazing band): the points it drops do not change the
/// rings the others are integrated with (a process's region of a distributed run, issue 37).
/// Its `index` argument holds the file indices as read, before `filter` dropped points.
DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::vector<std::size_t>& frames,
                                    const std::function<void(std::size_t)>& on_scan,
                                    const ScanFilter& filter, const ScanFilter& late_filter,
                                    bool read_ahead = true);
/// The same over every frame of `dataset`.
DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::function<void()>& on_scan = {}, bool read_ahead = true);

}  // namespace vdbmap
