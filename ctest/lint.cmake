# Size limits of the library (scripts/check_code_size.py): no file in lib/ over 600 lines, no function over 120.
# The second test checks that the checker still finds functions (lib/solver has many over 20 lines): it passes only
# on the checker's own report of it, a violation line naming a function of lib/solver and its length, then the
# summary with a nonzero count, then exit status 1 (a crash also exits 1, but prints a traceback and no summary).
add_test(NAME lint.code_size COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/scripts/check_code_size.py
                                     --max-file 600 --max-function 120 ${CMAKE_SOURCE_DIR}/lib ${CMAKE_SOURCE_DIR}/python)
add_test(NAME lint.code_size_detects
         COMMAND /bin/sh -c "/usr/bin/python3 \"$0\" --max-function 20 \"$1\"; echo \"check_code_size exit status $?\""
                 ${CMAKE_SOURCE_DIR}/scripts/check_code_size.py ${CMAKE_SOURCE_DIR}/lib/solver)
set_tests_properties(lint.code_size PROPERTIES LABELS "lint;quick")
set(ARIES_SIZE_FINDING "lib/solver/[^ ]+\\.[ch]pp:[0-9]+ [~A-Za-z_][~A-Za-z0-9_:<>]*: [0-9]+ lines \\(function limit 20")
set(ARIES_SIZE_SUMMARY "check_code_size: [0-9]+ functions, [1-9][0-9]* over the limits.check_code_size exit status 1")
set_tests_properties(lint.code_size_detects PROPERTIES LABELS "lint;quick" FAIL_REGULAR_EXPRESSION "Traceback"
                     PASS_REGULAR_EXPRESSION "${ARIES_SIZE_FINDING}.*${ARIES_SIZE_SUMMARY}")
