# SPDX-License-Identifier: Apache-2.0
# cmake -DINCLUDE_DIR=<libvdbmap/include> -DINSTALLED=<a.h,core/b.h,...> -DPLUGIN_DIRS=<d1,d2>
#       -P check_installed_headers.cmake   (lists separated by commas)
# Fails when an installed vdbmap header includes a vdbmap header that is not installed (an
# out-of-tree plugin could not compile it), or when a plugin source (not its test/ or bench/)
# includes one: everything a plugin author needs must be installed.
cmake_minimum_required(VERSION 3.16)
string(REPLACE "," ";" INSTALLED "${INSTALLED}")
string(REPLACE "," ";" PLUGIN_DIRS "${PLUGIN_DIRS}")
set(allowed Version.h ${INSTALLED})  # Version.h is generated and installed separately
set(errors "")

# Appends to `errors` every vdbmap header that `file` includes and that is not installed.
function(check_includes file who)
    file(STRINGS ${file} lines REGEX "^#include [<\"]vdbmap/")
    foreach(line ${lines})
        string(REGEX REPLACE "^#include [<\"]vdbmap/([^>\"]+)[>\"].*" "\\1" inc "${line}")
        if(NOT inc IN_LIST allowed)
            string(APPEND errors "${who} includes vdbmap/${inc}, which is not installed\n")
        endif()
    endforeach()
    set(errors "${errors}" PARENT_SCOPE)
endfunction()

foreach(header ${INSTALLED})
    if(EXISTS ${INCLUDE_DIR}/vdbmap/${header})
        check_includes(${INCLUDE_DIR}/vdbmap/${header} "installed vdbmap/${header}")
    else()
        string(APPEND errors "installed header vdbmap/${header} does not exist\n")
    endif()
endforeach()

foreach(dir ${PLUGIN_DIRS})
    file(GLOB_RECURSE sources ${dir}/*.h ${dir}/*.cpp)
    foreach(source ${sources})
        if(NOT source MATCHES "/(test|bench)/")
            check_includes(${source} ${source})
        endif()
    endforeach()
endforeach()

list(LENGTH INSTALLED count)
if(errors)
    message(FATAL_ERROR "${errors}")
endif()
message(STATUS "${count} installed headers include only installed headers; plugins need no other")
