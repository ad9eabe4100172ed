// SPDX-License-Identifier: Apache-2.0
// vdbmap.run(): a YAML pipeline, as `vdbmap run` runs it, from Python. Returns report.json's
// content as JSON text (the package turns it into a dict).
#include <tbb/global_control.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "Bindings.h"
#include "vdbmap/pipeline/Pipeline.h"
#include "vdbmap/pipeline/Report.h"

namespace vdbmap::python {
namespace {

std::string runPipeline(const std::string& config_path, const std::string& output_dir,
                        const std::vector<std::string>& overrides, int threads, bool quiet) {
    // The GIL is released for the run: its log lines reach Python's logging from any thread.
    py::gil_scoped_release release;
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      static_cast<std::size_t>(threads));
    auto pipeline = Pipeline::fromFile(config_path, overrides);
    const std::filesystem::path out = output_dir.empty()
                                          ? std::filesystem::path(pipeline->outputConfig().dir)
                                          : std::filesystem::path(output_dir);
    Report report;
    pipeline->run(out, report, quiet);
    return report.toJson(0);
}

}  // namespace

void registerRun(py::module_& m) {
    m.def("_run", &runPipeline, py::arg("config_path"), py::arg("output_dir"), py::arg("overrides"),
          py::arg("threads"), py::arg("quiet"));
}

}  // namespace vdbmap::python
