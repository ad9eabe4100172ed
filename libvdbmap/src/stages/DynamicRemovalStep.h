// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vdbmap/dynamic/DynamicDetector.h"
#include "vdbmap/dynamic/DynamicPoints.h"
#include "vdbmap/dynamic/MovingReturns.h"
#include "vdbmap/map/IntegrateDataset.h"
#include "stages/SharedDynamicDecisions.h"

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
    /// A distributed run (issue 37): tests the scans of `mine` (ascending) for every process,
    /// and takes the other processes' decisions for the scans of `integrated` through
    /// `all_gather` (a collective: every process calls it once, at the same point); filter()
    /// then tests only the scans no process decided. Nothing when disabled.
    void shareDecisions(const std::vector<std::size_t>& mine,
                        const std::vector<std::size_t>& integrated,
                        const std::function<std::vector<std::string>(const std::string&)>& all_gather);
    /// Writes `dynamic_points.ply` (a part file per process in a distributed run, merged by
    /// process 0: mergeDynamicPointParts) and stages.<stage>.dynamic_removal in the report.
    void finish(Context& ctx, const std::string& stage) const;
    double seconds() const { return detector_ ? detector_->stats().seconds : 0.0; }

private:
    const Dataset* dataset_ = nullptr;
    std::unique_ptr<DynamicDetector> detector_;
    DynamicPoints removed_;
    std::shared_ptr<MovingReturns> moving_;
    SharedDynamicDecisions shared_;
    bool sharing_ = false;
};

}  // namespace vdbmap::detail
