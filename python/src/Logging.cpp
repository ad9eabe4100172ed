// SPDX-License-Identifier: Apache-2.0
// vdbmap's log lines into Python's `logging` (logger "vdbmap"), from any thread: the sink takes
// the GIL, so the calls that run C++ work release it first (MapBindings, RunBindings).
#include "Bindings.h"

#include "vdbmap/core/Log.h"

namespace vdbmap::python {

void registerLogging(py::module_& m) {
    m.def(
        "_log_to_python",
        [](bool on) {
            if (!on) {
                setLogSink({});
                return;
            }
            setLogLevel(LogLevel::Debug);  // Python's logging filters by level
            setLogSink([](LogLevel level, const std::string& message) {
                py::gil_scoped_acquire gil;
                // An error inside logging must not unwind through C++ worker threads.
                try {
                    static const int kLevels[] = {10, 20, 30, 40, 50};  // DEBUG ... CRITICAL
                    py::module_::import("logging").attr("getLogger")("vdbmap").attr("log")(
                        kLevels[static_cast<int>(level)], message);
                } catch (py::error_already_set& e) {
                    e.discard_as_unraisable("vdbmap log sink");
                }
            });
        },
        py::arg("on"), "Send vdbmap's log lines to Python's logging (logger 'vdbmap'), or back to stderr");
}

}  // namespace vdbmap::python
