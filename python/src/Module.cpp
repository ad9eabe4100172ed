// SPDX-License-Identifier: Apache-2.0
#include "Bindings.h"

#include "vdbmap/Version.h"

PYBIND11_MODULE(_vdbmap, m) {
    m.doc() = "vdbmap: adaptive-TSDF mapping on OpenVDB (the C++ core; see the vdbmap package)";
    m.attr("__version__") = VDBMAP_VERSION_STRING;
    vdbmap::python::registerErrors(m);
    vdbmap::python::registerLogging(m);
    vdbmap::python::registerMap(m);
    vdbmap::python::registerRun(m);
    vdbmap::python::registerReaders(m);
}
