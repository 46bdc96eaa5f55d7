# Precompiled headers: parsing Eigen, GoogleTest and the standard library again
# in every file was most of the suite's build time on 2 cores (./tumble test
# builds three trees). Only third-party and standard headers go in: a change
# to our own headers must never leave a stale precompiled copy.
set(TUMBLE_PCH_COMMON <algorithm> <array> <cmath> <cstdint> <filesystem> <fstream>
    <optional> <span> <string> <vector> <Eigen/Core> <Eigen/Geometry>)

# tumble_precompile_headers(TARGET [GTEST]): the common headers, plus GoogleTest
# for a test binary.
function(tumble_precompile_headers target)
  set(_headers ${TUMBLE_PCH_COMMON})
  if("GTEST" IN_LIST ARGN)
    list(APPEND _headers <gtest/gtest.h>)
  endif()
  target_precompile_headers(${target} PRIVATE ${_headers})
  target_link_libraries(${target} PRIVATE Eigen3::Eigen)
  # Lets ccache reuse compiles against the precompiled header (clang stamps it
  # with its build time otherwise); see README (ccache sloppiness).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    target_compile_options(${target} PRIVATE "SHELL:-Xclang -fno-pch-timestamp")
  endif()
endfunction()
