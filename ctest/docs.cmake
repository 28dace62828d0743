# docs/options.md's tables are generated from the option declarations (aries-options-doc): the file in git must be
# exactly what the declarations make, so a documented default cannot differ from the code's. The second test shows
# that the check catches a hand edit: copies of the docs with one default changed must fail, naming the line.
add_test(NAME docs.options COMMAND aries-options-doc --check ${CMAKE_SOURCE_DIR}/docs/options.md)
add_test(NAME docs.options_detects
         COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/ctest/options_doc.py --tool $<TARGET_FILE:aries-options-doc>
                 --docs ${CMAKE_SOURCE_DIR}/docs/options.md --work ${CMAKE_BINARY_DIR}/docs_check)
set_tests_properties(docs.options docs.options_detects PROPERTIES LABELS "lint;quick")
