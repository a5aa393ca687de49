include(GNUInstallDirs)

# Project-wide warnings and sanitizers, applied to mire's own targets only. -Werror only with
# MIRE_WERROR (CI turns it on): a newer compiler's new warnings must not break a user's build.
function(mire_target_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  if(MIRE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(MIRE_SANITIZE OR MIRE_FUZZ)
    # PUBLIC: whatever uses a sanitized library (tests, fuzzers, a program built against the
    # installed package) must be compiled and linked the same way. Not only for the runtime:
    # Eigen allocates differently under ASan (__SANITIZE_ADDRESS__, Eigen/src/Core/util/Memory.h),
    # so a matrix allocated in the library and freed in an uninstrumented program is a bad free.
    target_compile_options(${target} PUBLIC -fsanitize=address,undefined)
    target_compile_options(${target} PRIVATE -fno-omit-frame-pointer)
    target_link_options(${target} PUBLIC -fsanitize=address,undefined)
  endif()
  if(MIRE_FUZZ)
    # Coverage for libFuzzer in every library (the ASan runtime provides the hooks elsewhere).
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()

# Precompiled headers for the targets whose every file includes the same heavy headers (the
# command, the tests, the benchmarks): Eigen, OpenCV's core and the standard
# library (the standard library alone with STD_ONLY), plus GoogleTest with GTEST. Not for the libraries, whose files differ in what they include
# and spend their time instantiating templates, not parsing (doc/install.md "Build time").
function(mire_precompile_headers target)
  cmake_parse_arguments(ARG "GTEST;STD_ONLY" "" "" ${ARGN})
  set(headers <algorithm> <cmath> <filesystem> <functional> <iostream> <map> <memory> <optional> <sstream>
              <string> <vector>)
  if(NOT ARG_STD_ONLY)
    list(APPEND headers <Eigen/Core> <Eigen/Geometry> <opencv2/core.hpp>)
  endif()
  if(ARG_GTEST)
    list(APPEND headers <gtest/gtest.h>)
  endif()
  target_precompile_headers(${target} PRIVATE ${headers})
endfunction()

# mire_add_module(<name> PUBLIC <targets...> PRIVATE <targets...>): a static library from every
# .cpp under the module's src/, public headers under <module>/include/mire/<module>/, exported
# and installed as mire::<name>. PUBLIC: what the public headers include; PRIVATE: what only the
# sources use (still listed for static linking, as $<LINK_ONLY:...>).
function(mire_add_module name)
  cmake_parse_arguments(ARG "" "" "PUBLIC;PRIVATE" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  add_library(mire_${name} STATIC ${sources})
  add_library(mire::${name} ALIAS mire_${name})
  target_include_directories(mire_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(mire_${name} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
  target_compile_features(mire_${name} PUBLIC cxx_std_17)
  set_target_properties(mire_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME ${name})
  mire_target_options(mire_${name})
  install(TARGETS mire_${name} EXPORT mireTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
