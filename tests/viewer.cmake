# SPDX-License-Identifier: Apache-2.0
# `vdbmap view` (docs/viewer.md). The path resolver's and the CLI's unit tests link the
# server library. The browser tests (LABEL browser) need Debian's chromium, node and the npm
# registry (first run: `npm ci` of tests/browser/package-lock.json into the build folder);
# they are left out of the sanitizer build (scripts/sanitize.sh: the server's code is
# covered there by ViewCommandTest) and with -DVDBMAP_BROWSER_TESTS=OFF.
if(TARGET ViewServedPathTest)
    target_link_libraries(ViewServedPathTest PRIVATE vdbmap_view_server)
endif()
if(TARGET ViewCommandTest)
    target_link_libraries(ViewCommandTest PRIVATE vdbmap_view_server)
endif()

option(VDBMAP_BROWSER_TESTS "Browser tests of the viewer (chromium, node, npm)" ON)
if(VDBMAP_BROWSER_TESTS AND NOT VDBMAP_SANITIZE AND TARGET vdbmap_app)
    set(_browser ${CMAKE_CURRENT_BINARY_DIR}/browser)
    set(_vdbmap $<TARGET_FILE:vdbmap_app>)
    set(_data_md ${PROJECT_SOURCE_DIR}/docs/DATA.md)
    add_test(NAME browser_setup
             COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/browser/setup.sh ${_browser})
    set_tests_properties(browser_setup PROPERTIES FIXTURES_SETUP browser_npm TIMEOUT 600)

    # A hand-made tileset (tests/browser/make_fixture.mjs): independent of the writer.
    add_test(NAME browser_fixture_tileset
             COMMAND node ${CMAKE_CURRENT_SOURCE_DIR}/browser/make_fixture.mjs ${_browser}/fixture)
    set_tests_properties(browser_fixture_tileset PROPERTIES FIXTURES_SETUP browser_fixture)
    add_test(NAME viewer_browser_fixture
             COMMAND node ${_browser}/viewer_test.mjs --vdbmap ${_vdbmap} --out ${_browser}/fixture
                     --data-md ${_data_md} --name fixture)
    set_tests_properties(viewer_browser_fixture PROPERTIES
                         FIXTURES_REQUIRED "browser_npm;browser_fixture" TIMEOUT 180)
    set(_browser_tests browser_setup browser_fixture_tileset viewer_browser_fixture)

    # A small simulated run through tests/browser/tiled_street.yaml (the demo pipeline, tiled,
    # ending in export.3dtiles): the writer's real tileset, textured, meshopt-compressed, with
    # levels of detail above several leaves.
    if(TARGET vdbmap_sim AND EXISTS ${PROJECT_SOURCE_DIR}/plugins/tiles3d/CMakeLists.txt)
        set(_sim_seq ${_browser}/sim_seq)
        set(_sim_run ${_browser}/sim_run)
        add_test(NAME browser_sim_run
                 COMMAND sh -c "rm -rf '${_sim_seq}' '${_sim_run}' && \
'$<TARGET_FILE:vdbmap_sim>' street --frames 6 --size 40 --seed 1 --gt-views 0 --quiet -o '${_sim_seq}' && \
'${_vdbmap}' run '${CMAKE_CURRENT_SOURCE_DIR}/browser/tiled_street.yaml' --set dataset.path='${_sim_seq}' \
-o '${_sim_run}' --quiet && test -s '${_sim_run}/3dtiles/tileset.json'")
        set_tests_properties(browser_sim_run PROPERTIES FIXTURES_SETUP browser_sim TIMEOUT 900)
        add_test(NAME viewer_browser_sim
                 COMMAND node ${_browser}/viewer_test.mjs --vdbmap ${_vdbmap} --out ${_sim_run}
                         --data-md ${_data_md} --name sim)
        add_test(NAME cesium_browser_sim
                 COMMAND node ${_browser}/cesium_test.mjs --vdbmap ${_vdbmap} --out ${_sim_run}
                         --name sim)
        set_tests_properties(viewer_browser_sim cesium_browser_sim PROPERTIES
                             FIXTURES_REQUIRED "browser_npm;browser_sim" TIMEOUT 180)
        list(APPEND _browser_tests browser_sim_run viewer_browser_sim cesium_browser_sim)
    endif()
    set_tests_properties(${_browser_tests} PROPERTIES LABELS "browser")
endif()
