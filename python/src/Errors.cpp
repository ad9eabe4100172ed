// SPDX-License-Identifier: Apache-2.0
// C++ errors as Python exceptions: one base class, vdbmap.Error, and one subclass per typed
// error of vdbmap/Error.h, each carrying the C++ message (docs/python.md, "Errors").
#include "Bindings.h"

#include "vdbmap/Error.h"

namespace vdbmap::python {

void registerErrors(py::module_& m) {
    // Static: the translator below raises them for the life of the interpreter.
    static py::exception<vdbmap::Error> error(m, "Error", PyExc_RuntimeError);
    static py::exception<vdbmap::ConfigError> config(m, "ConfigError", error.ptr());
    static py::exception<vdbmap::PluginError> plugin(m, "PluginError", error.ptr());
    // IoError: a file that cannot be read or written, or malformed data.
    static py::exception<vdbmap::IoError> data(m, "DataError", error.ptr());
    static py::exception<vdbmap::InvalidInput> invalid(m, "InvalidInputError", error.ptr());
    m.attr("IoError") = data;
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const vdbmap::ConfigError& e) {
            config(e.what());
        } catch (const vdbmap::PluginError& e) {
            plugin(e.what());
        } catch (const vdbmap::IoError& e) {
            data(e.what());
        } catch (const vdbmap::InvalidInput& e) {
            invalid(e.what());
        } catch (const vdbmap::Error& e) {
            error(e.what());
        }
    });
}

}  // namespace vdbmap::python
