# SPDX-License-Identifier: Apache-2.0
# Command-line tests of vdbmap-sim and `vdbmap eval`: a tiny street sequence, the ground truth
# scored against itself (F = 1), and clean failures on bad input.
if(TARGET vdbmap_sim AND TARGET vdbmap_app)
    set(_seq ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/seq)
    set(_run ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/run)
    add_test(NAME sim_cli_street_tiny
        COMMAND $<TARGET_FILE:vdbmap_sim> street -o ${_seq} --frames 2 --size 20 --no-images
                --gt-views 0 --quiet --threads 1)
    add_test(NAME sim_cli_rejects_unknown_scene
        COMMAND $<TARGET_FILE:vdbmap_sim> forest -o ${_seq}_bad)
    set_tests_properties(sim_cli_rejects_unknown_scene PROPERTIES WILL_FAIL TRUE)
    add_test(NAME eval_cli_gt_against_itself
        COMMAND sh -c "mkdir -p '${_run}' && cp '${_seq}/gt/mesh.ply' '${_run}/mesh.ply' && \
'$<TARGET_FILE:vdbmap_app>' eval --gt '${_seq}/gt' --run '${_run}' --json '${_run}/eval.json' \
--tau 0.05 && grep -q '\"fscore\": 1.0' '${_run}/eval.json'")
    set_tests_properties(eval_cli_gt_against_itself PROPERTIES DEPENDS sim_cli_street_tiny)
    add_test(NAME eval_cli_missing_run_fails
        COMMAND $<TARGET_FILE:vdbmap_app> eval --gt ${_seq}/gt --run ${_run}_missing)
    set_tests_properties(eval_cli_missing_run_fails PROPERTIES WILL_FAIL TRUE
                         DEPENDS sim_cli_street_tiny)
endif()
