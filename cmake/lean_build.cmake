# Build time is most of ./tumble test's time on 2 cores (it builds four trees),
# and most of that was parsing Eigen, GoogleTest and the standard library
# again in every file. So those headers are precompiled, and each target
# compiles as unity files of 8 sources (names at file scope in one target's
# sources must differ). Only third-party and standard headers are precompiled:
# a change to our own headers must never leave a stale precompiled copy.
set(TUMBLE_PCH_COMMON <algorithm> <array> <cmath> <cstdint> <filesystem> <fstream>
    <optional> <span> <string> <vector> <Eigen/Core> <Eigen/Geometry>)

# Precompiled once per tree, not once per target: each copy took 4-6 s, and
# 18 copies were a sixth of the release tree's compile time. tumble_pch serves
# the libraries and tools, tumble_pch_gtest (test/) adds GoogleTest. Every
# target compiles with the same flags, so one copy is valid for all; CMake's
# -Winvalid-pch with -Werror fails the build if ever it is not.
function(tumble_pch_target name)
  set(_anchor ${CMAKE_BINARY_DIR}/${name}.cpp)
  if(NOT EXISTS ${_anchor})
    file(WRITE ${_anchor} "")
  endif()
  add_library(${name} OBJECT ${_anchor})
  target_precompile_headers(${name} PRIVATE ${ARGN})
  _tumble_compile_like_ours(${name})
endfunction()

function(_tumble_compile_like_ours target)
  # -pthread (from spdlog for most targets) defines _REENTRANT, which the
  # standard headers read: one shared precompiled header needs it everywhere.
  target_compile_options(${target} PRIVATE -pthread)
  target_link_libraries(${target} PRIVATE Eigen3::Eigen tumble_warnings)
  # Lets ccache reuse compiles against the precompiled header (clang stamps it
  # with its build time otherwise); see docs/decisions/build.md (ccache sloppiness).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    target_compile_options(${target} PRIVATE "SHELL:-Xclang -fno-pch-timestamp")
  endif()
endfunction()

tumble_pch_target(tumble_pch ${TUMBLE_PCH_COMMON})

# tumble_lean_build(TARGET [GTEST]): the common headers precompiled (plus
# GoogleTest for a test binary), unity files of 8.
function(tumble_lean_build target)
  if("GTEST" IN_LIST ARGN)
    target_precompile_headers(${target} REUSE_FROM tumble_pch_gtest)
  else()
    target_precompile_headers(${target} REUSE_FROM tumble_pch)
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  _tumble_compile_like_ours(${target})
endfunction()
