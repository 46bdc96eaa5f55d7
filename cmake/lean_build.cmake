# Build time is most of ./tumble test's time on 2 cores (it builds four trees),
# and most of that was parsing Eigen, GoogleTest and the standard library
# again in every file. So each target precompiles those headers, and compiles
# as unity files of 8 sources (names at file scope in one target's sources
# must differ). Only third-party and standard headers are precompiled: a
# change to our own headers must never leave a stale precompiled copy.
set(TUMBLE_PCH_COMMON <algorithm> <array> <cmath> <cstdint> <filesystem> <fstream>
    <optional> <span> <string> <vector> <Eigen/Core> <Eigen/Geometry>)

# tumble_lean_build(TARGET [GTEST]): the common headers precompiled, plus
# GoogleTest for a test binary; unity files of 8.
function(tumble_lean_build target)
  set(_headers ${TUMBLE_PCH_COMMON})
  if("GTEST" IN_LIST ARGN)
    list(APPEND _headers <gtest/gtest.h>)
  endif()
  target_precompile_headers(${target} PRIVATE ${_headers})
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  target_link_libraries(${target} PRIVATE Eigen3::Eigen)
  # Lets ccache reuse compiles against the precompiled header (clang stamps it
  # with its build time otherwise); see README (ccache sloppiness).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    target_compile_options(${target} PRIVATE "SHELL:-Xclang -fno-pch-timestamp")
  endif()
endfunction()
