#!/usr/bin/env bash
# tumble's entry point: installs what the build needs, builds, and runs.
#   ./tumble test    build and run the whole suite (release, ASan+UBSan with fuzzers, TSan,
#                    and the drivers' tests cross-built for arm64, run under qemu-user)
#   ./tumble demo    build, then run tumbled on the default simulated extreme-motion run
#   ./tumble build   build the release tree only
#   ./tumble deb     build the Debian packages build/tumble_<version>_{amd64,arm64}.deb
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")"
root=$(pwd)
jobs=$(nproc)

packages=(
  build-essential cmake ninja-build pkg-config clang libclang-rt-14-dev
  libeigen3-dev libboost-dev libspdlog-dev libyaml-cpp-dev libpcap-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libnanoflann-dev robin-map-dev
  libsystemd-dev libglib2.0-dev liblcm-dev liblcm-bin liblcm-java default-jdk-headless
  gnuplot-nox iproute2
)
# The arm64 cross build (tests under qemu-user), the Debian packages and their
# install test (systemd-analyze, systemd-sysusers, deb-systemd-helper).
cross_packages=(crossbuild-essential-arm64 qemu-user dpkg-dev lintian systemd init-system-helpers)
# The :arm64 libraries that are Multi-Arch: same, so they install beside
# their amd64 versions (Eigen, CLI11, nanoflann, robin-map are headers only,
# architecture all).
arm64_packages=(libboost-dev libspdlog-dev libfmt-dev libpcap-dev libgtest-dev libgmock-dev
  libsystemd-dev libglib2.0-dev libyaml-cpp0.7)
# Not Multi-Arch: same in Debian 12: apt would remove the amd64 versions the
# native build needs, so these are unpacked into build/arm64-deps instead.
arm64_unpacked=(liblcm1 liblcm-dev libyaml-cpp-dev)

log() { printf '\033[1m[tumble]\033[0m %s\n' "$*" >&2; }

# ensure_packages [PKG...]: installs those missing (default: the native build's).
ensure_packages() {
  [ $# -gt 0 ] || set -- "${packages[@]}"
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  log "installing Debian packages: ${missing[*]}"
  local sudo=()
  [ "$(id -u)" -eq 0 ] || sudo=(sudo)
  "${sudo[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

ensure_arm64() {
  ensure_packages "${packages[@]}" "${cross_packages[@]}"
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    log "adding the arm64 architecture to dpkg"
    [ "$(id -u)" -eq 0 ] && dpkg --add-architecture arm64 || sudo dpkg --add-architecture arm64
  fi
  ensure_packages "${arm64_packages[@]/%/:arm64}"
  unpack_arm64_deps
}

# The arm64 packages that cannot be co-installed, unpacked into build/arm64-deps
# (toolchain file: TUMBLE_ARM64_DEPS). Their own shlibs entries go to
# build/arm64-deps/shlibs for dpkg-shlibdeps.
unpack_arm64_deps() {
  local dir=$root/build/arm64-deps
  [ "$(cat "$dir/unpacked" 2>/dev/null)" = "${arm64_unpacked[*]}" ] && return 0
  log "unpacking ${arm64_unpacked[*]} (arm64) into $dir"
  rm -rf "$dir"
  mkdir -p "$dir/debs"
  (cd "$dir/debs" && apt-get download -qq -o APT::Sandbox::User=root "${arm64_unpacked[@]/%/:arm64}")
  local deb
  for deb in "$dir"/debs/*.deb; do
    dpkg-deb -x "$deb" "$dir"
    dpkg-deb -I "$deb" shlibs >>"$dir/shlibs" 2>/dev/null || true
  done
  local lib=$dir/usr/lib/aarch64-linux-gnu
  sed -i "s|^prefix=/usr\$|prefix=$dir/usr|" "$lib/pkgconfig/lcm.pc"
  # libyaml-cpp-dev's link name and CMake targets point beside them, at the
  # runtime library: that is the installed libyaml-cpp0.7:arm64.
  local so
  for so in /usr/lib/aarch64-linux-gnu/libyaml-cpp.so.0.7*; do ln -sf "$so" "$lib/"; done
  echo "${arm64_unpacked[*]}" >"$dir/unpacked"
}

# configure DIR [cmake args...]: configure once, then let ninja re-run cmake as needed.
configure() {
  local dir=$1; shift
  if [ ! -f "$dir/build.ninja" ]; then
    cmake -S "$root" -B "$dir" -G Ninja "$@" >/dev/null
  fi
}

build_release() {
  configure build/release -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTUMBLE_WERROR=ON
  log "building build/release"
  cmake --build build/release -j "$jobs"
}

build_asan() {
  configure build/asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER=clang++ -DTUMBLE_WERROR=ON \
    -DTUMBLE_SANITIZE=address,undefined -DTUMBLE_FUZZ=ON -DTUMBLE_BENCH=OFF
  log "building build/asan (ASan + UBSan, libFuzzer targets)"
  cmake --build build/asan -j "$jobs"
}

build_tsan() {
  configure build/tsan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER=clang++ -DTUMBLE_WERROR=ON \
    -DTUMBLE_SANITIZE=thread -DTUMBLE_BENCH=OFF
  log "building build/tsan (ThreadSanitizer, threaded tests only)"
  cmake --build build/tsan -j "$jobs" --target tumble_daemon_threaded_tests
}

# run_ctest NAME DIR [ctest args...]: runs ctest, keeps its summary for the total.
summary=()
failed_suites=0
run_ctest() {
  local name=$1 dir=$2; shift 2
  local out="$dir/ctest-summary.txt"
  log "running $name tests"
  local rc=0
  ctest --test-dir "$dir" -j "$jobs" --output-on-failure "$@" 2>&1 | tee "$out" || rc=$?
  [ "${PIPESTATUS[0]}" -eq 0 ] || rc=1
  local total passed failed skipped
  total=$(sed -n 's/.*tests passed, [0-9]* tests\{0,1\} failed out of \([0-9]*\).*/\1/p' "$out" | tail -1)
  failed=$(sed -n 's/.*tests passed, \([0-9]*\) tests\{0,1\} failed out of.*/\1/p' "$out" | tail -1)
  skipped=$(grep -c '\*\*\*Skipped' "$out" || true)
  total=${total:-0}; failed=${failed:-0}
  passed=$((total - failed - skipped))
  summary+=("$name: $passed passed, $failed failed, $skipped skipped")
  [ "$rc" -eq 0 ] || failed_suites=$((failed_suites + 1))
  totals_passed=$((${totals_passed:-0} + passed))
  totals_failed=$((${totals_failed:-0} + failed))
  totals_skipped=$((${totals_skipped:-0} + skipped))
}

# timed LABEL COMMAND...: runs it here (run_ctest keeps totals), notes its time.
timings=()
timed() {
  local label=$1 start=$SECONDS
  shift
  "$@"
  timings+=("$label $((SECONDS - start)) s")
}

cmd_test() {
  ensure_packages "${packages[@]}" "${cross_packages[@]}"
  timed "release build" build_release
  timed "release tests" run_ctest release build/release
  timed "asan build" build_asan
  timed "asan tests" run_ctest "asan+ubsan (with fuzzers)" build/asan
  timed "tsan build" build_tsan
  timed "tsan tests" run_ctest tsan build/tsan -L threaded --no-tests=ignore
  timed "arm64 build" build_arm64 "${arm64_test_targets[@]}"
  timed "arm64 tests" run_ctest "arm64 (qemu-user, drivers)" build/arm64 --timeout 300 \
    -L "^($(IFS='|'; echo "${arm64_test_targets[*]}"))\$"
  echo
  printf '  time:'; printf ' %s;' "${timings[@]}"; echo
  for s in "${summary[@]}"; do echo "  $s"; done
  if [ "${totals_skipped:-0}" -gt 0 ]; then
    log "skipped tests need ../shared/fixtures (see README); their reasons are in the ctest output above"
  fi
  echo "total: ${totals_passed:-0} passed, ${totals_failed:-0} failed, ${totals_skipped:-0} skipped"
  [ "$failed_suites" -eq 0 ]
}

# What ./tumble test runs on arm64 under qemu-user: the drivers, the code that
# reads bytes (char signedness, alignment). The rest of the arm64 tree is not
# run yet: tumbled --replay hangs under qemu-user (README, On arm64).
arm64_test_targets=(tumble_rs16_tests tumble_mti_tests tumble_pcap_tests)

# build_arm64 [TARGET...]: the release tree cross-compiled for arm64 (default: all of it).
build_arm64() {
  ensure_arm64
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  configure build/arm64 -DCMAKE_TOOLCHAIN_FILE="$root/cmake/aarch64-linux-gnu.cmake" \
    -DTUMBLE_ARM64_DEPS="$root/build/arm64-deps" "${launcher[@]}" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTUMBLE_WERROR=ON -DTUMBLE_BENCH=OFF
  log "building build/arm64 (cross-compiled for arm64) ${*:-}"
  local targets=()
  [ $# -eq 0 ] || targets=(--target "$@")
  cmake --build build/arm64 -j "$jobs" "${targets[@]}"
}

# The Debian packages of the release trees, checked by lintian (errors fail;
# the warnings left are explained in README, Install on a robot).
cmd_deb() {
  build_release
  build_arm64
  local tree arch deb
  for tree in release arm64; do
    arch=$(dpkg --print-architecture)
    [ "$tree" = arm64 ] && arch=arm64
    deb=$("$root/packaging/build-deb.sh" "build/$tree" "$arch" build)
    log "built $deb; lintian:"
    lintian --fail-on error "$deb"
  done
}

cmd_demo() {
  ensure_packages
  build_release
  exec "$root/tools/demo.sh" "$root/build/release" "$@"
}

timed "arm64 build" build_arm64 "${arm64_test_targets[@]}"
timed "arm64 tests" run_ctest "arm64 (qemu-user, drivers)" build/arm64 --timeout 300 \
    -L "^($(IFS='|'; echo "${arm64_test_targets[*]}"))\$"
printf '  time:'; printf ' %s;' "${timings[@]}"; echo
for s in "${summary[@]}"; do echo "  $s"; done
