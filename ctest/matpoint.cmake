# CLI tests of aries-matpoint (label "cli"). Each test runs ctest/check_matpoint.py, which runs the binary and checks
# its output (JSON structure and values, closed-form results, the uniaxial path, error handling: exit code AND the
# one-line "aries-matpoint: error:" message). See the docstring of check_matpoint.py for the modes.
set(ARIES_MATPOINT_CHECKER ${CMAKE_CURRENT_LIST_DIR}/check_matpoint.py)

function(aries_matpoint_check name)
  add_test(NAME matpoint.${name}
           COMMAND /usr/bin/python3 ${ARIES_MATPOINT_CHECKER} $<TARGET_FILE:aries-matpoint> ${ARGN})
  set_tests_properties(matpoint.${name} PROPERTIES LABELS "cli;quick" TIMEOUT 60)
endfunction()

# -json: keys, entry counts (9/4/6 and 81/16/36), symmetric Hessian, PSD projection; I4/I6 only where they apply.
aries_matpoint_check(json.iarap_tet json --entries 9 --without I4 --without I6
                     -- -energy iarap -F 1.1,0.2,0,-0.1,0.9,0.05,0,0.3,1.2)
aries_matpoint_check(json.iarap_tet_inverted json --entries 9 --without I4
                     -- -energy iarap -F 1.2,0,0,0,0.9,0,0,0,-0.4)
aries_matpoint_check(json.fiber_tet json --entries 9 --with I4 --without I6
                     -- -energy fiber -gamma 50 -fiber 1,2,2 -F 1.1,0.2,0,-0.1,0.9,0.05,0,0.3,1.2)
aries_matpoint_check(json.shape_target_tet json --entries 9 --without I4
                     -- -energy shape_target -target 1.2,0.1,0,0.1,0.9,0,0,0,1 -F 1.1,0.2,0,-0.1,0.9,0.05,0,0.3,1.2)
aries_matpoint_check(json.iarap_planar json --entries 4 --without I4 --without I6
                     -- -energy iarap -F 1.1,0.2,-0.1,0.9)
aries_matpoint_check(json.alx_planar json --entries 4 --with I4 --without I6
                     -- -energy alx -fiber 1,1 -F 1.1,0.2,-0.1,0.9)
aries_matpoint_check(json.bw46s_cloth json --entries 6 --with I4 --with I6
                     -- -energy bw46s -fiber 1,0 -fiber2 1,1 -F 1.1,0.2,-0.1,0.9,0.3,0.1)
aries_matpoint_check(json.bw_cloth json --entries 6 --with I4 --with I6
                     -- -energy bw -fiber 1,0 -fiber2 0,1 -F 1.1,0.2,-0.1,0.9,0.3,0.1)
aries_matpoint_check(json.bw46_cloth json --entries 6 --without I4 --without I6
                     -- -energy bw46 -F 1.1,0.2,-0.1,0.9,0.3,0.1)

# Values against closed forms derived by hand (iarap at F = diag(1.1,1,1) with E = 1e4, nu = 0.3, ...).
foreach(case iarap_tet_uniaxial iarap_tet_triaxial arap_svd_tet iarap_planar alx_tet bw461_cloth bw46_cloth)
  aries_matpoint_check(closed_form.${case} closed-form ${case})
endforeach()

# -path uniaxial: effective modulus and lateral contraction at small strain (3D and plane strain).
aries_matpoint_check(path.uniaxial_tet path --shape tet)
aries_matpoint_check(path.uniaxial_planar path --shape planar)

# Bad arguments: exit code 1 and exactly one line "aries-matpoint: error: ..." on stderr.
aries_matpoint_check(error.wrong_F_count error --contains "-F" -- -energy iarap -F 1,2)
aries_matpoint_check(error.unknown_energy error --contains "foo" -- -energy foo -F 1,0,0,1)
aries_matpoint_check(error.nu_out_of_range error --contains "-nu" -- -energy iarap -nu 0.7 -F 1,0,0,1)
aries_matpoint_check(error.unknown_option error --contains "-gama" -- -energy fiber -gamma 1 -gama 2 -F 1,0,0,1)
aries_matpoint_check(error.singularity_on_iarap_lin error --contains "-singularity"
                     -- -energy iarap_lin -singularity barrier -F 1,0,0,1)
aries_matpoint_check(error.non_numeric_E error --contains "-E" -- -energy iarap -E abc -F 1,0,0,1)
aries_matpoint_check(error.unknown_singularity_mode error --contains "sometimes"
                     -- -energy iarap -singularity sometimes -F 1,0,0,1)
aries_matpoint_check(error.energy_not_for_cloth error --contains "iarap" -- -energy iarap -F 1,0,0,1,0,0)
aries_matpoint_check(error.bw461_non_orthogonal error --contains "bw46s"
                     -- -energy bw461 -fiber 1,0 -fiber2 1,1 -F 1,0,0,1,0,0)
aries_matpoint_check(error.json_with_path error --contains "-json" -- -energy iarap -path uniaxial -json)
aries_matpoint_check(error.no_F_no_path error -- -energy iarap)

# -help lists this tool's options, the material options and the energies as docs/options.md does (one declaration).
aries_matpoint_check(help help --docs ${CMAKE_SOURCE_DIR}/docs/options.md)
