# SPDX-License-Identifier: Apache-2.0
# vdbmap_add_plugin(NAME <name> SOURCES <src...> [LINK <targets...>] [NO_INSTALL])
#
# Builds the run-time plugin module `vdbmap_plugin_<name>.so`: hidden visibility (only the
# entry symbol from VDBMAP_PLUGIN is exported), linked against vdbmap::vdbmap, installed to
# <prefix>/lib/vdbmap/plugins. In-tree plugins and out-of-tree plugins use this same function;
# it ships in the installed CMake package.
function(vdbmap_add_plugin)
    cmake_parse_arguments(ARG "NO_INSTALL" "NAME;OUTPUT_DIRECTORY" "SOURCES;LINK" ${ARGN})
    if(NOT ARG_NAME)
        message(FATAL_ERROR "vdbmap_add_plugin: NAME is required")
    endif()
    if(NOT ARG_SOURCES)
        message(FATAL_ERROR "vdbmap_add_plugin(${ARG_NAME}): SOURCES is required")
    endif()
    set(target vdbmap_plugin_${ARG_NAME})
    add_library(${target} MODULE ${ARG_SOURCES})
    if(TARGET vdbmap::vdbmap)
        target_link_libraries(${target} PRIVATE vdbmap::vdbmap)
    else()
        target_link_libraries(${target} PRIVATE vdbmap)
    endif()
    if(ARG_LINK)
        target_link_libraries(${target} PRIVATE ${ARG_LINK})
    endif()
    target_compile_features(${target} PRIVATE cxx_std_17)
    set_target_properties(${target} PROPERTIES
        PREFIX ""
        OUTPUT_NAME ${target}
        CXX_VISIBILITY_PRESET hidden
        VISIBILITY_INLINES_HIDDEN ON)
    if(ARG_OUTPUT_DIRECTORY)
        set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})
    elseif(DEFINED VDBMAP_PLUGIN_BUILD_DIR)
        set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${VDBMAP_PLUGIN_BUILD_DIR})
    endif()
    if(NOT ARG_NO_INSTALL)
        include(GNUInstallDirs)
        install(TARGETS ${target} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/vdbmap/plugins)
    endif()
endfunction()
