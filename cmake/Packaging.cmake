# SPDX-License-Identifier: Apache-2.0
# Exported CMake package: find_package(vdbmap CONFIG REQUIRED) + vdbmap::vdbmap + vdbmap_add_plugin().
include(CMakePackageConfigHelpers)
set(VDBMAP_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/vdbmap)
install(EXPORT vdbmapTargets NAMESPACE vdbmap:: DESTINATION ${VDBMAP_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/vdbmapConfig.cmake.in
    ${CMAKE_CURRENT_BINARY_DIR}/vdbmapConfig.cmake INSTALL_DESTINATION ${VDBMAP_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/vdbmapConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/vdbmapConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/vdbmapConfigVersion.cmake
              ${CMAKE_CURRENT_SOURCE_DIR}/cmake/VdbmapPlugin.cmake
        DESTINATION ${VDBMAP_CMAKE_DIR})
