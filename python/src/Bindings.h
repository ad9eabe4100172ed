// SPDX-License-Identifier: Apache-2.0
// The parts of the Python module `vdbmap._vdbmap`, one register function per concept.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace vdbmap::python {

namespace py = pybind11;

void registerErrors(py::module_& m);   ///< Errors.cpp
void registerLogging(py::module_& m);  ///< Logging.cpp
void registerMap(py::module_& m);      ///< MapBindings.cpp
void registerRun(py::module_& m);      ///< RunBindings.cpp
void registerReaders(py::module_& m);  ///< ReaderBindings.cpp

}  // namespace vdbmap::python
