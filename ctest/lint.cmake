# Size limits of the library (scripts/check_code_size.py): no file in lib/ over 600 lines, no function over 120.
# The second test checks that the checker still finds functions (lib/solver has many over 20 lines).
add_test(NAME lint.code_size COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/check_code_size.py
                                     --max-file 600 --max-function 120 ${CMAKE_SOURCE_DIR}/lib)
add_test(NAME lint.code_size_detects COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/check_code_size.py
                                             --max-function 20 ${CMAKE_SOURCE_DIR}/lib/solver)
set_tests_properties(lint.code_size PROPERTIES LABELS "lint")
set_tests_properties(lint.code_size_detects PROPERTIES LABELS "lint" WILL_FAIL TRUE)
