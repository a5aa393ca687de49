# `cmake --install`: the libraries and headers, the `mire` command, the specs under share/mire,
# a CMake package (find_package(mire) → mire::calibration, mire::metrology, mire::mechanism,
# mire::datasets, mire::pipeline, mire::support) and a pkg-config file (doc/install.md).
include(CMakePackageConfigHelpers)
set(MIRE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/mire)

install(EXPORT mireTargets NAMESPACE mire:: DESTINATION ${MIRE_CMAKE_DIR} FILE mireTargets.cmake)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/mireConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/mireConfig.cmake INSTALL_DESTINATION ${MIRE_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mireConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/mireConfig.cmake ${PROJECT_BINARY_DIR}/mireConfigVersion.cmake
        DESTINATION ${MIRE_CMAKE_DIR})

# pkgconfig/ sits in the libdir: one ".." per libdir component, one for pkgconfig itself.
file(RELATIVE_PATH MIRE_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
string(REGEX REPLACE "/$" "" MIRE_PC_TO_PREFIX "${MIRE_PC_TO_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/mire.pc.in ${PROJECT_BINARY_DIR}/mire.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/mire.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
