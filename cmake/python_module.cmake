# The Python module aries_kernels (python/aries_kernels.cpp, docs/python.md): build/python/aries_kernels*.so, used
# with PYTHONPATH=build/python. Built by default where pybind11 is found (scripts/install-deps.sh installs Debian's
# pybind11-dev); -DARIES_PYTHON=OFF skips it. The module reads materials with the solver's own option reader
# (fem/material_options.cpp, core/options.cpp: compiled into the module, position-independent) and links PETSc for it.
option(ARIES_PYTHON "Build the Python module aries_kernels (needs pybind11)" ON)
# scripts/test.sh sets it: the README's test command must build and test the module, not skip it quietly.
option(ARIES_REQUIRE_PYTHON "Fail the configuration when the Python module cannot be built" OFF)
if(ARIES_PYTHON)
  # Debian's interpreter: its numpy and scipy are the ones the module and its tests use.
  if(NOT Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python COMPONENTS Interpreter Development.Module)
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 CONFIG QUIET)
  if(pybind11_FOUND AND Python_FOUND)
    pybind11_add_module(aries_python MODULE NO_EXTRAS python/aries_kernels.cpp
                        ${CMAKE_CURRENT_SOURCE_DIR}/lib/fem/material_options.cpp
                        ${CMAKE_CURRENT_SOURCE_DIR}/lib/core/options.cpp)
    set_target_properties(aries_python PROPERTIES OUTPUT_NAME aries_kernels
                          LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/python)
    target_link_libraries(aries_python PRIVATE aries_energies PkgConfig::PETSC MPI::MPI_CXX)
    set(ARIES_PYTHON_MODULE_DIR ${CMAKE_BINARY_DIR}/python)
    set(ARIES_PYTHON_INTERPRETER ${Python_EXECUTABLE})
    message(STATUS "aries: Python module aries_kernels in ${ARIES_PYTHON_MODULE_DIR} (${Python_EXECUTABLE})")
  else()
    set(why "pybind11 or Python's development files not found (scripts/install-deps.sh installs pybind11-dev python3-dev)")
    if(ARIES_REQUIRE_PYTHON)
      message(FATAL_ERROR "aries: ARIES_REQUIRE_PYTHON: ${why}")
    endif()
    message(STATUS "aries: no Python module: ${why}")
  endif()
endif()
