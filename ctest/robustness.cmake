# Robustness: bad input (one error line, exit 1, no output files; 1 and 2 ranks), kill and restart,
# failure policies, determinism. The bad-input cases are listed by ctest/bad_input.py itself.
# The configuration fails if the listing fails or lists nothing: the cases must not vanish from the suite silently.
execute_process(COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/ctest/bad_input.py --list
                OUTPUT_VARIABLE ARIES_BAD_INPUT_CASES ERROR_VARIABLE ARIES_BAD_INPUT_ERR
                RESULT_VARIABLE ARIES_BAD_INPUT_RC OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT ARIES_BAD_INPUT_RC EQUAL 0 OR ARIES_BAD_INPUT_CASES STREQUAL "")
  message(FATAL_ERROR "ctest/bad_input.py --list failed (exit status '${ARIES_BAD_INPUT_RC}') or listed no bad-input "
                      "case.\nstdout:\n${ARIES_BAD_INPUT_CASES}\nstderr:\n${ARIES_BAD_INPUT_ERR}")
endif()
# Every case on one rank; a representative subset on two (the collective error path is shared by all cases).
set(ARIES_BAD_INPUT_NP2 missing_mesh truncated_mesh degenerate_cell fiber_count unknown_bc_set strict_unknown_option
    missing_options_file curved_surface_read_flat cloth_energy_planar_mesh h5_mesh_not_converted h5_mesh_metis
    h5_mesh_old_format fiber_zero target_keyframe_order coarse_mesh_other_body)
foreach(case ${ARIES_BAD_INPUT_NP2})
  if(NOT case IN_LIST ARIES_BAD_INPUT_CASES)
    message(FATAL_ERROR "bad-input case '${case}' (two-rank subset) is not listed by ctest/bad_input.py --list: "
                        "${ARIES_BAD_INPUT_CASES}")
  endif()
endforeach()
foreach(case ${ARIES_BAD_INPUT_CASES})
  set(ranks_list 1)
  if(case IN_LIST ARIES_BAD_INPUT_NP2)
    list(APPEND ranks_list 2)
  endif()
  foreach(ranks ${ranks_list})
    add_test(NAME robustness.bad_input.${case}.np${ranks}
             COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/ctest/bad_input.py ${case} --aries $<TARGET_FILE:aries-app>
                     --root ${CMAKE_SOURCE_DIR} --work ${CMAKE_BINARY_DIR}/robustness/bad_input.np${ranks} --ranks ${ranks})
    # PROCESSORS 1 on both rank counts: a bad-input run stops at its error, and its two ranks spend most of their 1.5 s
    # starting Open MPI (0.3 s of CPU measured), so it need not hold both of a 2-core machine's slots.
    set_tests_properties(robustness.bad_input.${case}.np${ranks} PROPERTIES LABELS "robustness" PROCESSORS 1
                         TIMEOUT 120 FAIL_REGULAR_EXPRESSION "FAIL:")
  endforeach()
  set_property(TEST robustness.bad_input.${case}.np1 APPEND PROPERTY LABELS quick)  # a second each
endforeach()

foreach(case kill_restart failure_policy determinism)
  add_test(NAME robustness.${case}
           COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/ctest/robustness.py ${case} --aries $<TARGET_FILE:aries-app>
                   --root ${CMAKE_SOURCE_DIR} --work ${CMAKE_BINARY_DIR}/robustness/${case})
  set_tests_properties(robustness.${case} PROPERTIES LABELS "robustness" FIXTURES_REQUIRED aries_meshes
                       PROCESSORS 2 TIMEOUT 600 FAIL_REGULAR_EXPRESSION "FAIL:")
endforeach()
