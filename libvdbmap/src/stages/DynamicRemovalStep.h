// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <memory>
#include <string>

#include "vdbmap/dynamic/DynamicDetector.h"
#include "vdbmap/dynamic/DynamicPoints.h"
#include "vdbmap/dynamic/MovingReturns.h"
#include "vdbmap/map/IntegrateDataset.h"

namespace vdbmap {
class Context;
class OptionSpec;
}  // namespace vdbmap

namespace vdbmap::detail {

/// Declares integrate.atsdf's `dynamic_*` options (docs/dynamic.md), bound to `config`.
void declareDynamicOptions(OptionSpec& spec, DynamicRemovalConfig& config);

/// Moving-object removal inside an integrating stage: the scan filter that drops the dynamic
/// points of each scan before integration and keeps them, then the outputs.
class DynamicRemovalStep {
public:
    /// Without `config.enabled` the filter is empty and finish() writes nothing. With it, the
    /// context gets the moving returns the filter fills (Context::movingReturns()).
    DynamicRemovalStep(Context& ctx, const DynamicRemovalConfig& config);
    /// The filter for integrateDataset (empty when disabled).
    ScanFilter filter();
    /// Writes `dynamic_points.ply` (a part file per process in a distributed run, merged by
    /// process 0: mergeDynamicPointParts) and stages.<stage>.dynamic_removal in the report.
    void finish(Context& ctx, const std::string& stage) const;
    double seconds() const { return detector_ ? detector_->stats().seconds : 0.0; }

private:
    const Dataset* dataset_ = nullptr;
    std::unique_ptr<DynamicDetector> detector_;
    DynamicPoints removed_;
    std::shared_ptr<MovingReturns> moving_;
};

}  // namespace vdbmap::detail
