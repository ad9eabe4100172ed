# SPDX-License-Identifier: Apache-2.0
# vdbmap_set_warnings(target): project warnings, PRIVATE so they never leak to users (kiss-icp).
function(vdbmap_set_warnings target)
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-unused-parameter)
    if(VDBMAP_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()
