# SPDX-License-Identifier: Apache-2.0
# Command-line tests of vdbmap-sim and `vdbmap eval`: a tiny street sequence, the ground truth
# scored against itself (F = 1), and clean failures on bad input.
if(TARGET vdbmap_sim AND TARGET vdbmap_app)
    # A failure test passes only on the exact exit code and message (never on a crash).
    set(_expect_exit ${CMAKE_CURRENT_SOURCE_DIR}/scripts/expect_exit.sh)
    set(_seq ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/seq)
    set(_run ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/run)
    add_test(NAME sim_cli_street_tiny
        COMMAND $<TARGET_FILE:vdbmap_sim> street -o ${_seq} --frames 2 --size 20 --no-images
                --gt-views 0 --quiet --threads 1)
    add_test(NAME sim_cli_rejects_unknown_scene
        COMMAND bash ${_expect_exit} 2 "scene: forest not in {street,suv}"
                $<TARGET_FILE:vdbmap_sim> forest -o ${_seq}_bad)
    add_test(NAME eval_cli_gt_against_itself
        COMMAND sh -c "mkdir -p '${_run}' && cp '${_seq}/gt/mesh.ply' '${_run}/mesh.ply' && \
'$<TARGET_FILE:vdbmap_app>' eval --gt '${_seq}/gt' --run '${_run}' --json '${_run}/eval.json' \
--tau 0.05 && grep -q '\"fscore\": 1.0' '${_run}/eval.json'")
    set_tests_properties(eval_cli_gt_against_itself PROPERTIES DEPENDS sim_cli_street_tiny)
    # `vdbmap run` on config/experiments/truncation.yaml: with a 1-scan working set the second scan moves
    # leaves to the compact store; the map at rest keeps the issue's <= 16 B per active voxel.
    set(_atsdf_run ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/atsdf_run)
    add_test(NAME atsdf_cli_run_compact_map
        COMMAND sh -c "'$<TARGET_FILE:vdbmap_app>' run '${PROJECT_SOURCE_DIR}/config/experiments/truncation.yaml' --set dataset.path='${_seq}' --set integrate.atsdf.working_set_scans=1 -o '${_atsdf_run}' --quiet && test -s '${_atsdf_run}/map.vdb' && test -s '${_atsdf_run}/mesh.ply' && python3 -c \"import json, sys; s = json.load(open(sys.argv[1]))['stages']['integrate.atsdf']; assert s['leaves_retired'] > 0, s; assert 0 < s['bytes_per_active_voxel'] <= 16.0, s\" '${_atsdf_run}/report.json'")
    set_tests_properties(atsdf_cli_run_compact_map PROPERTIES DEPENDS sim_cli_street_tiny)
    # The surround rig: a generic-layout sequence whose dataset.yaml gives eval the cameras of
    # the camera-seen area (found next to gt/, or named with --dataset and --set).
    set(_rig ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/rig)
    set(_rig_run ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/rig_run)
    add_test(NAME sim_cli_rig_tiny
        COMMAND $<TARGET_FILE:vdbmap_sim> street -o ${_rig} --frames 2 --size 20 --rig surround
                --rig-width 96 --rig-height 54 --gt-views 0 --quiet --threads 1)
    add_test(NAME eval_cli_rig_camera_seen
        COMMAND sh -c "mkdir -p '${_rig_run}/semantic' && \
cp '${_rig}/gt/mesh.ply' '${_rig_run}/semantic/mesh.ply' && \
'$<TARGET_FILE:vdbmap_app>' eval --gt '${_rig}/gt' --run '${_rig_run}' --json '${_rig_run}/a.json' && \
grep -q 'rig/dataset.yaml' '${_rig_run}/a.json' && grep -q '\"rear\"' '${_rig_run}/a.json' && \
grep -q '\"frames\": 2' '${_rig_run}/a.json' && \
'$<TARGET_FILE:vdbmap_app>' eval --gt '${_rig}/gt' --run '${_rig_run}' --json '${_rig_run}/b.json' \
--dataset '${_rig}/dataset.yaml' --set dataset.num_frames=1 && \
grep -q '\"frames\": 1' '${_rig_run}/b.json'")
    set_tests_properties(eval_cli_rig_camera_seen PROPERTIES DEPENDS sim_cli_rig_tiny)
    add_test(NAME eval_cli_rig_bad_set_fails
        COMMAND bash ${_expect_exit} 2
                "--set dataset.no_such_key=1: dataset: unknown key 'no_such_key'; valid keys: format,"
                $<TARGET_FILE:vdbmap_app> eval --gt ${_rig}/gt --run ${_rig_run}
                --dataset ${_rig}/dataset.yaml --set dataset.no_such_key=1)
    set_tests_properties(eval_cli_rig_bad_set_fails PROPERTIES DEPENDS eval_cli_rig_camera_seen)
    add_test(NAME eval_cli_missing_run_fails
        COMMAND bash ${_expect_exit} 1
                "vdbmap eval: --run ${_run}_missing: not a folder"
                $<TARGET_FILE:vdbmap_app> eval --gt ${_seq}/gt --run ${_run}_missing)
    set_tests_properties(eval_cli_missing_run_fails PROPERTIES DEPENDS sim_cli_street_tiny)
    # Traffic (issue 33): the static truth has no ghost, a run without removal has some.
    set(_traffic ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/traffic)
    set(_traffic_run ${CMAKE_CURRENT_BINARY_DIR}/sim_eval_cli/traffic_run)
    add_test(NAME sim_cli_traffic_tiny
        COMMAND $<TARGET_FILE:vdbmap_sim> street -o ${_traffic} --frames 3 --traffic 2
                --no-images --gt-views 0 --quiet --threads 1)
    add_test(NAME eval_cli_traffic_ghosts
        COMMAND sh -c "mkdir -p '${_traffic_run}/gt_copy' && cp '${_traffic}/gt/mesh.ply' '${_traffic_run}/gt_copy/mesh.ply' && '$<TARGET_FILE:vdbmap_app>' eval --gt '${_traffic}/gt' --run '${_traffic_run}/gt_copy' --json '${_traffic_run}/gt.json' --quiet && '$<TARGET_FILE:vdbmap_app>' run '${PROJECT_SOURCE_DIR}/config/experiments/street.yaml' --set dataset.path='${_traffic}' --set integrate.atsdf.voxel_size_m=0.2 --set integrate.atsdf.dynamic_removal=false -o '${_traffic_run}/run' --quiet && '$<TARGET_FILE:vdbmap_app>' eval --gt '${_traffic}/gt' --run '${_traffic_run}/run' --json '${_traffic_run}/run.json' --quiet && python3 -c \"import json, sys; g = json.load(open(sys.argv[1]))['traffic']; r = json.load(open(sys.argv[2]))['traffic']; assert g['ghost_area_m2'] == 0 and g['swept_ground_area_m2'] > 50 and g['moving_points'] is None, g; assert r['ghost_area_m2'] > 5 and r['ghost_fraction'] > 0, r\" '${_traffic_run}/gt.json' '${_traffic_run}/run.json'")
    set_tests_properties(eval_cli_traffic_ghosts PROPERTIES DEPENDS sim_cli_traffic_tiny)
    add_test(NAME sim_cli_traffic_suv_rejected
        COMMAND bash ${_expect_exit} 2 "vdbmap-sim: --traffic is for the street scene, not 'suv'"
                $<TARGET_FILE:vdbmap_sim> suv -o ${_traffic}_suv --traffic 1)
endif()
