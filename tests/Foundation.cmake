# SPDX-License-Identifier: Apache-2.0
# Foundation tests that need more than their own executable: the test plugins, the built
# `vdbmap` app, and an install + out-of-tree build of examples/plugin_template.
set(_vdbmap_test_plugins vdbmap_plugin_testgood vdbmap_plugin_badabi vdbmap_plugin_nosymbol
    vdbmap_plugin_badreg)
foreach(test_target PluginLoaderTest CliTest PipelineTest InfoCommandTest)
    if(TARGET ${test_target})
        add_dependencies(${test_target} ${_vdbmap_test_plugins})
    endif()
endforeach()
foreach(test_target CliTest InfoCommandTest)
    if(TARGET ${test_target} AND TARGET vdbmap_app)
        add_dependencies(${test_target} vdbmap_app)
    endif()
endforeach()
# StageRegistryTest and ConfigFilesTest load every in-tree plugin this build has, and fail
# when one of them does not load (support/BuiltPlugins.h).
set(_vdbmap_built_plugins "")
foreach(plugin texture semantic tiles3d cgal)
    if(TARGET vdbmap_plugin_${plugin})
        list(APPEND _vdbmap_built_plugins ${plugin})
    endif()
endforeach()
string(REPLACE ";" "," _vdbmap_built_plugins_csv "${_vdbmap_built_plugins}")
foreach(test_target StageRegistryTest ConfigFilesTest)
    if(TARGET ${test_target})
        target_compile_definitions(${test_target} PRIVATE
            VDBMAP_BUILT_PLUGINS="${_vdbmap_built_plugins_csv}")
        foreach(plugin ${_vdbmap_built_plugins})
            add_dependencies(${test_target} vdbmap_plugin_${plugin})
        endforeach()
    endif()
endforeach()
if(TARGET ConfigFilesTest)
    target_link_libraries(ConfigFilesTest PRIVATE yaml-cpp)
endif()

# Installs the build into a scratch prefix, builds examples/plugin_template against the
# installed package with find_package(vdbmap CONFIG REQUIRED), and runs it via `vdbmap run`.
if(VDBMAP_BUILD_APPS)
    add_test(NAME install_and_plugin_template
        COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/scripts/install_plugin_template.sh
                ${PROJECT_BINARY_DIR} ${PROJECT_SOURCE_DIR} ${CMAKE_COMMAND})
    set_tests_properties(install_and_plugin_template PROPERTIES TIMEOUT 300 LABELS "install" COST 30)
endif()

# The installed headers (libvdbmap/CMakeLists.txt) are closed under #include and cover what
# the in-tree plugins and the plugin template include.
string(REPLACE ";" "," _vdbmap_installed_headers "${VDBMAP_INSTALLED_HEADERS}")
add_test(NAME installed_headers_closed
    COMMAND ${CMAKE_COMMAND} -DINCLUDE_DIR=${PROJECT_SOURCE_DIR}/libvdbmap/include
            -DINSTALLED=${_vdbmap_installed_headers}
            -DPLUGIN_DIRS=${PROJECT_SOURCE_DIR}/plugins,${PROJECT_SOURCE_DIR}/examples/plugin_template
            -P ${CMAKE_CURRENT_SOURCE_DIR}/scripts/check_installed_headers.cmake)
