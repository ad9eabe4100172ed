# SPDX-License-Identifier: Apache-2.0
# `vdbmap view` (docs/viewer.md): the path resolver's unit test links the server library;
# the browser tests (LABEL browser) need Debian's chromium and the npm registry.
if(TARGET ViewServedPathTest)
    target_link_libraries(ViewServedPathTest PRIVATE vdbmap_view_server)
endif()
if(TARGET ViewCommandTest)
    target_link_libraries(ViewCommandTest PRIVATE vdbmap_view_server)
endif()
