# End-to-end cases of the solver (ctest/e2e/*.py hold them by topic with their expected values; ctest/e2e.py runs
# one), on 1 and 2 ranks where the parallel path is what a case checks, on one where a second rank proves nothing that
# the *_ranks_agree comparisons do not. A fixture generates the test-size meshes once (cached in meshes/cache). Label
# "quick": a minute's selection for the edit-compile-test loop (ctest -L quick; README).
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

# Both rank counts: the parallel path (faces, loads and supports shared across ranks, the overlap of cloth meshes, halos
# of the nested iteration's transfer) is part of what the case checks, or the case costs a few seconds.
foreach(ranks 1 2)
  aries_e2e(scramble scramble ${ranks})
  aries_e2e(inside_out_mollifier inside_out_mollifier ${ranks})
  aries_e2e(inside_out_barrier inside_out_barrier ${ranks})
  aries_e2e(inside_out_gamg inside_out_gamg ${ranks})
  aries_e2e(cylinder_reaction cylinder_reaction ${ranks})
  aries_e2e(moving_supports moving_supports ${ranks})
  aries_e2e(surface_handle surface_handle ${ranks})
  aries_e2e(exact_start exact_start ${ranks})
  aries_e2e(mesh_faces mesh_faces ${ranks})
  aries_e2e(surface_loads surface_loads ${ranks})
  aries_e2e(shell_pressure shell_pressure ${ranks})
  aries_e2e(pressure_open_wall pressure_open_wall ${ranks})
  aries_e2e(symmetry_supports symmetry_supports ${ranks})
  aries_e2e(run_resources run_resources ${ranks})
  aries_e2e(ortho_cube ortho_cube ${ranks})
  aries_e2e(safeguard_basic safeguard_basic ${ranks})
  aries_e2e(local_solve local_solve ${ranks})
  aries_e2e(cloth_hang cloth_hang ${ranks})
  aries_e2e(cloth_sphere cloth_sphere ${ranks})
  aries_e2e(cloth_appendix_d cloth_appendix_d ${ranks})
  aries_e2e(uv_disk uv_disk ${ranks})
  aries_e2e(shape_target shape_target ${ranks})
  aries_e2e(shape_keyframes shape_keyframes ${ranks})
  aries_e2e(caricature caricature ${ranks})
  aries_e2e(static_scramble static_scramble ${ranks})
  aries_e2e(rest_continued rest_continued ${ranks})
  aries_e2e(dynamic_scramble_volume dynamic_scramble_volume ${ranks})
  aries_e2e(dynamic_scramble_fiber_volume dynamic_scramble_fiber_volume ${ranks})
  aries_e2e(anisotropic_scramble_band anisotropic_scramble_band ${ranks})
  aries_e2e(mollifier_band_default mollifier_band_default ${ranks})
  aries_e2e(unused_option_warning unused_option_warning ${ranks})
  aries_e2e(meshio_xdmf meshio_xdmf ${ranks})
  aries_e2e(output_fields output_fields ${ranks})
  aries_e2e(multigrid_rule multigrid_rule ${ranks})
  aries_e2e(nested_static_scramble nested_static_scramble ${ranks})
  aries_e2e(nested_patch nested_patch ${ranks})
  aries_e2e(nested_inside_out nested_inside_out ${ranks})
  aries_e2e(hex_elements hex_elements ${ranks})
  aries_e2e(p2_elements p2_elements ${ranks})
endforeach()
# One rank: their two-rank runs (up to 100 s each) repeated the one-rank checks. The parallel assembly of each element,
# load and start they use is compared across ranks by ranks_agree (P1: a scramble with supports), hex_ranks_agree,
# p2_ranks_agree, nested_ranks_agree and inflate_ranks_agree (follower pressure); static_scramble and the inside-out
# cases run on both rank counts, and so do shell_pressure (follower, P1 and P2), pressure_open_wall (dead, P1, P2 and
# hexahedra) and surface_loads.
aries_e2e(pressure_elements pressure_elements 1)
# One case per element shape, side by side: the shapes of PATCH_ENERGIES in ctest/e2e/supports.py (a shape added there
# is added here).
foreach(shape tet hex p2 planar cloth)
  aries_e2e(patch_tests_${shape} patch_tests_${shape} 1)
endforeach()
aries_e2e(detached_start detached_start 1)
aries_e2e(inside_out_density1 inside_out_density1 1)
aries_e2e(nested_cell_files nested_cell_files 1)
# Two ranks only, as before: one rank takes twice as long on its own (209 s against 100 s for the hexahedral case),
# the suite's longest test.
aries_e2e(hex_degenerate_starts hex_degenerate_starts 2)
aries_e2e(p2_degenerate_starts p2_degenerate_starts 2)
aries_e2e(newton_variants newton_variants 1)
aries_e2e(extrapolate extrapolate 1)
aries_e2e(predictor_free_fall predictor_free_fall 1)
aries_e2e(version version 1)
aries_e2e(help help 1)
aries_e2e(gravity_origin gravity_origin 1)
aries_e2e(scripts scripts 1)
aries_e2e(paraview paraview 1)
set_tests_properties(e2e.paraview.np1 PROPERTIES SKIP_RETURN_CODE 77)
aries_e2e(output_times output_times 1)
aries_e2e(safeguard_l2 safeguard_l2 1)
aries_e2e(kim_aa_fails kim_aa_fails 1)
aries_e2e(no_false_convergence no_false_convergence 1)
aries_e2e(ranks_agree ranks_agree 1)
set_tests_properties(e2e.ranks_agree.np1 PROPERTIES PROCESSORS 2)
aries_e2e(active_ranks_agree active_ranks_agree 1)
aries_e2e(inflate_ranks_agree inflate_ranks_agree 1)
aries_e2e(nested_ranks_agree nested_ranks_agree 1)
set_tests_properties(e2e.nested_ranks_agree.np1 PROPERTIES PROCESSORS 2)
aries_e2e(hex_ranks_agree hex_ranks_agree 1)
set_tests_properties(e2e.hex_ranks_agree.np1 PROPERTIES PROCESSORS 2)
aries_e2e(p2_ranks_agree p2_ranks_agree 1)
set_tests_properties(e2e.p2_ranks_agree.np1 PROPERTIES PROCESSORS 2)
aries_e2e(parallel_io parallel_io 1)
set_tests_properties(e2e.parallel_io.np1 PROPERTIES PROCESSORS 2)
set_tests_properties(e2e.active_ranks_agree.np1 PROPERTIES PROCESSORS 2)

# Every shipped options file runs -options_left/-strict clean (one rank; the bunny scene also on two).
file(GLOB ARIES_OPTION_FILES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/options/*.yml)
foreach(f ${ARIES_OPTION_FILES})
  get_filename_component(scene ${f} NAME_WE)
  aries_e2e(options.${scene} options:${scene} 1)
endforeach()
aries_e2e(options.bunny_inside_out options:bunny_inside_out 2)

# The quick selection: one short case per area (reaction force, supports, loads, pressure, cloth, safeguard, orthotropy,
# gravity, CLI), a few seconds each.
foreach(name cylinder_reaction moving_supports run_resources cloth_hang safeguard_basic ortho_cube shell_pressure
        gravity_origin version help)
  set_property(TEST e2e.${name}.np1 APPEND PROPERTY LABELS quick)
endforeach()
