# End-to-end cases of the solver (ctest/e2e.py holds each case and its expected values), 1 and 2 ranks.
# A fixture generates the test-size meshes once (cached in meshes/cache).
set(ARIES_PY /usr/bin/python3)
set(ARIES_E2E_WORK ${CMAKE_BINARY_DIR}/e2e)

add_test(NAME e2e.meshes COMMAND ${CMAKE_SOURCE_DIR}/meshes/generate.sh all test)
set_tests_properties(e2e.meshes PROPERTIES FIXTURES_SETUP aries_meshes LABELS "e2e" TIMEOUT 900)

function(aries_e2e name case ranks)
  add_test(NAME e2e.${name}.np${ranks}
           COMMAND ${ARIES_PY} ${CMAKE_SOURCE_DIR}/ctest/e2e.py ${case} --aries $<TARGET_FILE:aries-app>
                   --root ${CMAKE_SOURCE_DIR} --work ${ARIES_E2E_WORK}/${name}.np${ranks} --ranks ${ranks})
  set_tests_properties(e2e.${name}.np${ranks} PROPERTIES FIXTURES_REQUIRED aries_meshes LABELS "e2e"
                       PROCESSORS ${ranks} TIMEOUT 600 FAIL_REGULAR_EXPRESSION "FAIL:")
endfunction()

foreach(ranks 1 2)
  aries_e2e(scramble scramble ${ranks})
  aries_e2e(inside_out_mollifier inside_out_mollifier ${ranks})
  aries_e2e(inside_out_barrier inside_out_barrier ${ranks})
  aries_e2e(inside_out_gamg inside_out_gamg ${ranks})
  aries_e2e(cylinder_reaction cylinder_reaction ${ranks})
  aries_e2e(ortho_cube ortho_cube ${ranks})
  aries_e2e(safeguard_basic safeguard_basic ${ranks})
  aries_e2e(cloth_hang cloth_hang ${ranks})
  aries_e2e(cloth_sphere cloth_sphere ${ranks})
  aries_e2e(cloth_appendix_d cloth_appendix_d ${ranks})
  aries_e2e(uv_disk uv_disk ${ranks})
  aries_e2e(shape_target shape_target ${ranks})
  aries_e2e(shape_keyframes shape_keyframes ${ranks})
  aries_e2e(caricature caricature ${ranks})
  aries_e2e(static_scramble static_scramble ${ranks})
  aries_e2e(rest_continued rest_continued ${ranks})
  aries_e2e(inside_out_density1 inside_out_density1 ${ranks})
  aries_e2e(unused_option_warning unused_option_warning ${ranks})
endforeach()
aries_e2e(newton_variants newton_variants 1)
aries_e2e(version version 1)
aries_e2e(output_times output_times 1)
aries_e2e(safeguard_l2 safeguard_l2 1)
aries_e2e(kim_aa_fails kim_aa_fails 1)
aries_e2e(no_false_convergence no_false_convergence 1)
aries_e2e(ranks_agree ranks_agree 1)
set_tests_properties(e2e.ranks_agree.np1 PROPERTIES PROCESSORS 2)
aries_e2e(active_ranks_agree active_ranks_agree 1)
set_tests_properties(e2e.active_ranks_agree.np1 PROPERTIES PROCESSORS 2)

# Every shipped options file runs -options_left/-strict clean (one rank; the bunny scene also on two).
file(GLOB ARIES_OPTION_FILES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/options/*.yml)
foreach(f ${ARIES_OPTION_FILES})
  get_filename_component(scene ${f} NAME_WE)
  aries_e2e(options.${scene} options:${scene} 1)
endforeach()
aries_e2e(options.bunny_inside_out options:bunny_inside_out 2)
