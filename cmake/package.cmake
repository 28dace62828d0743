# The installed C++ package: `cmake --install build --prefix P`, then in a downstream project
#   find_package(aries 0.1 CONFIG REQUIRED)      # CMAKE_PREFIX_PATH=P
#   target_link_libraries(app PRIVATE aries::kernels)
# aries::kernels carries the headers of lib/kernels and lib/energies (installed under include/aries), the static
# library of the energy registry's evaluation (aries_energies) and Eigen (found again by the package's config).
# The solver's executables install to bin/. docs/cpp-package.md; ctest package.downstream builds examples/downstream.
include(CMakePackageConfigHelpers)

set_target_properties(aries_kernels PROPERTIES EXPORT_NAME kernel_headers)
set_target_properties(aries_energies PROPERTIES EXPORT_NAME kernels)
install(TARGETS aries_kernels aries_energies EXPORT ariesTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/aries)
install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/lib/kernels ${CMAKE_CURRENT_SOURCE_DIR}/lib/energies
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/aries FILES_MATCHING PATTERN "*.hpp")
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/generated/energies/catalog.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/aries/energies)

set(ARIES_PACKAGE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/aries)
install(EXPORT ariesTargets NAMESPACE aries:: DESTINATION ${ARIES_PACKAGE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/ariesConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/package/ariesConfig.cmake
                              INSTALL_DESTINATION ${ARIES_PACKAGE_DIR})
# 0.x: a minor release may change the kernels' interface, so only the same major.minor is compatible.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/package/ariesConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/package/ariesConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/package/ariesConfigVersion.cmake
        DESTINATION ${ARIES_PACKAGE_DIR})

foreach(tool aries-app aries-matpoint)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()
