# The kernels as a library (docs/python.md, docs/cpp-package.md), label "library":
#   python.*            the Python module against aries-matpoint -json, central differences and bad input
#                       (ctest/python_module.py; registered where the module is built: cmake/python_module.cmake)
#   package.downstream  `cmake --install` into a fresh prefix, examples/downstream configured and built against it,
#                       its numbers equal to aries-matpoint's; a version the package is not compatible with is refused
if(ARIES_PYTHON_MODULE_DIR)
  foreach(mode matpoint fd errors)
    add_test(NAME python.${mode}
             COMMAND ${ARIES_PYTHON_INTERPRETER} ${CMAKE_CURRENT_LIST_DIR}/python_module.py
                     $<TARGET_FILE:aries-matpoint> ${mode})
    set_tests_properties(python.${mode} PROPERTIES LABELS "library" TIMEOUT 120
                         ENVIRONMENT "PYTHONPATH=${ARIES_PYTHON_MODULE_DIR}")
  endforeach()
  set_tests_properties(python.fd python.errors PROPERTIES LABELS "library;quick")  # seconds; matpoint runs the CLI ~40x
  add_test(NAME python.example COMMAND ${ARIES_PYTHON_INTERPRETER} ${CMAKE_SOURCE_DIR}/examples/python/stretch_strip.py
                                       --check --out ${CMAKE_BINARY_DIR}/python-example)
  set_tests_properties(python.example PROPERTIES LABELS "library" TIMEOUT 120
                       ENVIRONMENT "PYTHONPATH=${ARIES_PYTHON_MODULE_DIR};MPLBACKEND=Agg")
endif()
add_test(NAME package.downstream
         COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/package_downstream.sh ${CMAKE_BINARY_DIR} ${CMAKE_SOURCE_DIR}
                 $<TARGET_FILE:aries-matpoint>)
set_tests_properties(package.downstream PROPERTIES LABELS "library" TIMEOUT 300)
