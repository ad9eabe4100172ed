# SPDX-License-Identifier: Apache-2.0
# The documentation against the tree (tests/scripts/check_docs.py): every relative link and
# anchor of README.md, config/README.md and docs/ resolves, every repository path they cite
# exists, and docs/plugins.md lists exactly the installed headers. Python 3 standard library
# only; well under a second.
string(REPLACE ";" "," _vdbmap_docs_headers "${VDBMAP_INSTALLED_HEADERS}")
add_test(NAME docs_check
    COMMAND python3 ${CMAKE_CURRENT_SOURCE_DIR}/scripts/check_docs.py
            --root ${PROJECT_SOURCE_DIR} --installed ${_vdbmap_docs_headers})
set_tests_properties(docs_check PROPERTIES LABELS "docs")
