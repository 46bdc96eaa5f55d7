# Cross-compiles for arm64 with Debian's cross toolchain (crossbuild-essential-arm64)
# and the :arm64 multiarch libraries; tests run under qemu-user.
#   cmake -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake -DTUMBLE_ARM64_DEPS=DIR
# DIR holds the arm64 packages that are not Multi-Arch: same in Debian 12
# (liblcm1, liblcm-dev, libyaml-cpp-dev): installing them with apt would remove
# their amd64 versions, which the native build needs, so `./tumble` unpacks
# them there instead (see arm64_deps in the script).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# GCC notes that passing std::pair changed ABI in GCC 10.1; everything here is
# built by one GCC, so the note is noise.
# -ffp-contract=off: GCC fuses a*b+c into one FMA instruction by default
# (-ffp-contract=fast, also under -std=c++20), rounding once where amd64
# rounds twice (baseline x86-64 has no FMA, so its code is the same with or
# without the flag). Fused, the arm64 tumbled's trajectory of the default run
# parts from the amd64 one after 3.2 s and is up to 17 cm off, and one
# expression fused differently in two places broke
# Icp.ReusingNeighboursGivesTheSameMatchesAsSearchingEveryIteration. Unfused,
# both architectures give bit-identical trajectories (docs/decisions/build.md).
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi -ffp-contract=off")

set(TUMBLE_ARM64_DEPS "" CACHE PATH "Unpacked arm64 packages that cannot be co-installed with amd64")
# Toolchain files are read again for each try_compile: pass the directory on.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES TUMBLE_ARM64_DEPS)
if(TUMBLE_ARM64_DEPS)
  list(PREPEND CMAKE_PREFIX_PATH "${TUMBLE_ARM64_DEPS}/usr")
  set(ENV{PKG_CONFIG_PATH} "${TUMBLE_ARM64_DEPS}/usr/lib/aarch64-linux-gnu/pkgconfig")
endif()
# pkgconf's cross personality: only arm64 .pc files (/usr/lib/aarch64-linux-gnu/pkgconfig).
set(PKG_CONFIG_EXECUTABLE aarch64-linux-gnu-pkg-config CACHE FILEPATH "")

# Programs (lcm-gen, javac) come from the build machine; libraries, headers
# and CMake packages from the multiarch paths of the target.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)

# ctest, gtest_discover_tests and add_test run arm64 binaries through this.
# -L /: the arm64 dynamic loader of libc6:arm64 (/lib/ld-linux-aarch64.so.1),
# the same glibc build as the libc.so.6 that every :arm64 library's search
# path finds in /lib/aarch64-linux-gnu. Not -L /usr/aarch64-linux-gnu: its
# loader is libc6-arm64-cross's, another build (2.36-8cross1 beside
# 2.36-9+deb12u14), and a loader and a libc from different builds disagree on
# their private data: the first pthread_create walked its stack cache list
# from the wrong address and looped for ever (docs/decisions/build.md).
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /)
