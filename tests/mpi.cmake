# SPDX-License-Identifier: Apache-2.0
# vdbmap-mpi under mpirun (issue 13): only when the build has it (VDBMAP_WITH_MPI and MPI
# found). The test sets OMPI_ALLOW_RUN_AS_ROOT* in the mpirun child only (CI runs as root).
if(TARGET vdbmap_mpi AND TARGET vdbmap_app AND MPIEXEC_EXECUTABLE)
    add_executable(MpiRunTest ${CMAKE_CURRENT_SOURCE_DIR}/mpi/MpiRunTest.cpp)
    target_link_libraries(MpiRunTest PRIVATE vdbmap vdbmap_simeval vdbmap_test_support
        Catch2::Catch2WithMain nlohmann_json::nlohmann_json)
    target_compile_definitions(MpiRunTest PRIVATE VDBMAP_MPIEXEC="${MPIEXEC_EXECUTABLE}")
    vdbmap_set_warnings(MpiRunTest)
    add_dependencies(MpiRunTest vdbmap_mpi vdbmap_app vdbmap_plugin_texture vdbmap_plugin_semantic)
    vdbmap_test_cost(MpiRunTest cost)
    catch_discover_tests(MpiRunTest WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR} TEST_SPEC ${VDBMAP_TEST_SPEC}
        PROPERTIES TIMEOUT 900 LABELS "mpi" COST ${cost})
endif()
