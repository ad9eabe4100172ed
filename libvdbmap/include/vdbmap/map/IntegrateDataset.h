// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <functional>

#include "vdbmap/io/Dataset.h"

namespace vdbmap {

class AtsdfIntegrator;

/// What integrateDataset did (its integration counts are in the integrator's totals()).
struct DatasetIntegration {
    ScanReadStats read;      ///< summed over the scans
    double seconds = 0.0;    ///< wall time of the whole loop, reading included
    double read_wait_s = 0.0;  ///< of which waiting for a scan that was not read yet
};

/// The scan loop of integrate.atsdf: every frame of `dataset` in order, in the LiDAR frame with
/// its pose T_W_L. With `read_ahead`, scan i + 1 is read and filtered on another thread while
/// scan i is integrated (reading overlaps integration; at most one scan in flight). Calls
/// `on_scan` after each scan (progress). A read error is rethrown as thrown by
/// Dataset::loadScan, after the scans before it were integrated.
DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::function<void()>& on_scan = {}, bool read_ahead = true);

}  // namespace vdbmap
