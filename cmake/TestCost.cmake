# SPDX-License-Identifier: Apache-2.0
# ctest -j starts the tests in decreasing COST (CTestCostData.txt only exists after a first
# run, so a fresh clone in CI would start them in file order). The executables below hold the
# end-to-end cases that take longest (seconds at -O3, minutes under the sanitizer build); given
# a cost they start first instead of running alone at the end of the suite. Figures: seconds
# of the slowest case under scripts/sanitize.sh (2-core machine), for the order only.
set(VDBMAP_TEST_COSTS
    TiledPipelineTest 400
    MpiRunTest 300
    TilesInFlightTest 150
    LidarLabelStageTest 200
    AdaptiveVsFixedTest 70
    FaultTest 50
    ResumeTest 50
    TextureRigTest 40
    SemanticStageTest 25
    CompactTsdfTest 20
    TilePlanTest 20)

# vdbmap_test_cost(<executable> <out-var>): its COST above, 0 if it is not listed.
function(vdbmap_test_cost name out)
    list(FIND VDBMAP_TEST_COSTS ${name} i)
    set(cost 0)
    if(i GREATER -1)
        math(EXPR j "${i} + 1")
        list(GET VDBMAP_TEST_COSTS ${j} cost)
    endif()
    set(${out} ${cost} PARENT_SCOPE)
endfunction()

# The sanitizer suite (scripts/sanitize.sh) leaves out the end-to-end cases tagged [heavy]:
# each repeats with more runs a path that a lighter case also drives under the sanitizers
# (docs/developing.md lists them and their lighter twins); the release suite runs them all.
# Every catch_discover_tests call passes TEST_SPEC ${VDBMAP_TEST_SPEC}.
if(VDBMAP_SANITIZE)
    set(VDBMAP_TEST_SPEC "~[heavy]")
else()
    set(VDBMAP_TEST_SPEC "")
endif()
