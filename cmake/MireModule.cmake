# Project-wide warnings and sanitizers, applied to mire's own targets only.
function(mire_target_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Werror)
  if(MIRE_FUZZ)
    # Coverage for libFuzzer in every library; clang's extra warnings do not gate fuzzing.
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -Wno-error)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  elseif(MIRE_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# mire_add_module(<name> DEPS <targets...>): a library from every .cpp beside the
# module's CMakeLists.txt (sources live next to their headers' module), public headers
# under <module>/include/mire/<module>/, exported as mire::<name>.
function(mire_add_module name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  add_library(mire_${name} STATIC ${sources})
  add_library(mire::${name} ALIAS mire_${name})
  target_include_directories(mire_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(mire_${name} PUBLIC ${ARG_DEPS})
  set_target_properties(mire_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  mire_target_options(mire_${name})
endfunction()
