#!/usr/bin/env bash
# The Debian package, installed, upgraded and purged in a throwaway root,
# never on this machine's own system:
#   deb_install_test.sh BUILD_DIR SOURCE_DIR
# dpkg --root=DIR keeps its database in DIR; --force-script-chrootless runs
# the maintainer scripts here with DPKG_ROOT=DIR (DIR has no shell to chroot
# into), and they honour it: systemd-sysusers --root, deb-systemd-helper's
# DPKG_ROOT, and no systemctl or udevadm on the running system.
# --force-depends: DIR's database knows none of the libraries tumble needs.
set -euo pipefail
build=$(readlink -f "$1")
src=$(readlink -f "$2")
skip() { echo "SKIPPED: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "needs root (dpkg installs files owned by root)"
for tool in dpkg-deb dpkg-shlibdeps systemd-analyze systemd-sysusers deb-systemd-helper; do
  command -v "$tool" >/dev/null || skip "$tool not installed (Debian packages dpkg-dev, systemd, init-system-helpers)"
done

prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$build/CMakeCache.txt")
[ "$prefix" = /usr ] || skip "the tree's prefix is $prefix; the package is built from a tree configured for /usr"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }
arch=$(dpkg --print-architecture)
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
first=$("$src/packaging/build-deb.sh" "$build" "$arch" "$work/debs")
upgrade=$("$src/packaging/build-deb.sh" "$build" "$arch" "$work/debs" "$version+upgrade1")

root=$work/root
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates"
: >"$root/var/lib/dpkg/status"
# dpkg's output (mostly the dependencies --force-depends overrides) only when it fails.
in_root() {
  dpkg --root="$root" --force-script-chrootless --force-depends --log="$work/dpkg.log" "$@" >"$work/dpkg.out" 2>&1 ||
    { cat "$work/dpkg.out" >&2; fail "dpkg $*"; }
}
installed_version() { dpkg-query --root="$root" -W -f='${Status} ${Version}' tumble 2>/dev/null || true; }
files_outside_dpkg() { (cd "$root" && find . \( -type f -o -type l \) ! -path './var/lib/dpkg/*' | sort); }

echo "== install $(basename "$first")"
in_root -i "$first"
[ "$(installed_version)" = "install ok installed $version" ] || fail "status: $(installed_version)"
for f in usr/bin/tumbled usr/bin/tumble-sim usr/bin/tumble-eval usr/bin/tumble-calib usr/bin/tumble-dump \
         usr/bin/tumble-spy usr/share/java/tumble-lcmtypes.jar usr/lib/systemd/system/tumbled.service \
         usr/bin/tumble-view usr/share/tumble/view/index.html usr/lib/systemd/system/tumble-view.service \
         usr/lib/sysusers.d/tumble.conf usr/lib/udev/rules.d/99-tumble-mti.rules usr/lib/sysctl.d/60-tumble.conf \
         etc/tumble/tumbled.yaml \
         usr/share/doc/tumble/copyright usr/share/doc/tumble/lcm-interface.md \
         usr/share/man/man1/tumbled.1.gz usr/share/man/man1/tumble-sim.1.gz usr/share/man/man1/tumble-eval.1.gz \
         usr/share/man/man1/tumble-calib.1.gz usr/share/man/man1/tumble-dump.1.gz usr/share/man/man1/tumble-spy.1.gz \
         usr/share/man/man1/tumble-view.1.gz usr/share/tumble/lcmtypes/map_t.lcm usr/include/tumble/map_t.hpp \
         usr/share/tumble/lcmtypes/odometry_t.lcm usr/share/tumble/lcmtypes/registration_t.lcm \
         usr/share/tumble/lcmtypes/status_t.lcm usr/share/tumble/lcmtypes/scan_t.lcm \
         usr/include/tumble/odometry_t.hpp usr/include/tumble/registration_t.hpp \
         usr/include/tumble/status_t.hpp usr/include/tumble/scan_t.hpp \
         usr/share/pkgconfig/tumble-lcmtypes.pc usr/share/cmake/tumble-lcmtypes/tumble-lcmtypes-config.cmake; do
  [ -e "$root/$f" ] || fail "/$f not installed"
done
dpkg-query --root="$root" -W -f='${Conffiles}\n' tumble | grep -q '^ /etc/tumble/tumbled.yaml ' ||
  fail "/etc/tumble/tumbled.yaml is not a conffile"
grep -q '^tumble:' "$root/etc/passwd" || fail "postinst did not create the user tumble (systemd-sysusers)"
grep -q '^dialout:.*tumble' "$root/etc/group" || fail "tumble is not in group dialout"

echo "== systemd-analyze verify the installed unit"
# --root: ExecStart's /usr/bin/tumbled is looked for inside the root. The
# targets the unit orders itself after come from this machine's systemd,
# copied into a copy of the root, so the purge check below stays exact.
verify_root=$work/verify-root
cp -a "$root" "$verify_root"
cp -an /usr/lib/systemd/system/. "$verify_root/usr/lib/systemd/system/"
analyze=$(systemd-analyze verify --root="$verify_root" /usr/lib/systemd/system/tumbled.service \
  /usr/lib/systemd/system/tumble-view.service 2>&1) || fail "systemd-analyze verify: $analyze"
[ -z "$analyze" ] || fail "systemd-analyze verify warns: $analyze"

echo "== the installed tumbled --print-config"
"$root/usr/bin/tumbled" --config "$root/etc/tumble/tumbled.yaml" --print-config >"$work/config.txt" ||
  fail "tumbled --print-config exited $?"
grep -q 'device: "\{0,1\}/dev/ttyUSB0' "$work/config.txt" || fail "--print-config does not show imu.device: $(cat "$work/config.txt")"

echo "== the installed tumbled reads /etc/tumble/tumbled.yaml without --config"
"$root/usr/bin/tumbled" --help | grep -q 'default: /etc/tumble/tumbled.yaml where it exists' ||
  fail "tumbled --help does not name /etc/tumble/tumbled.yaml as its default configuration"

echo "== the installed LCM headers compile, found through pkg-config"
cflags=$(PKG_CONFIG_PATH="$root/usr/share/pkgconfig" pkg-config --define-variable=prefix="$root/usr" --cflags tumble-lcmtypes) ||
  fail "pkg-config tumble-lcmtypes"
printf '#include <tumble/%s.hpp>\n' odometry_t registration_t status_t scan_t |
  c++ -std=c++17 -fsyntax-only $cflags -x c++ - || fail "the installed headers do not compile with $cflags"

echo "== the installed C++ subscriber example builds, finding the headers with find_package(tumble-lcmtypes)"
cmake -S "$root/usr/share/doc/tumble/examples/subscriber_cpp" -B "$work/example" -DCMAKE_PREFIX_PATH="$root/usr" \
  >"$work/example.log" 2>&1 && cmake --build "$work/example" >>"$work/example.log" 2>&1 ||
  { cat "$work/example.log" >&2; fail "the installed C++ example does not build"; }
grep -rqF -- "$root/usr/include" "$work/example/CMakeFiles" ||
  fail "the example did not use the installed headers"

echo "== edit the conffile, upgrade to $(basename "$upgrade")"
sed -i 's|device: "/dev/ttyUSB0"|device: "/dev/xsens"|' "$root/etc/tumble/tumbled.yaml"
in_root -i "$upgrade"
[ "$(installed_version)" = "install ok installed $version+upgrade1" ] || fail "status after upgrade: $(installed_version)"
grep -q 'device: "/dev/xsens"' "$root/etc/tumble/tumbled.yaml" || fail "the upgrade lost the edit of tumbled.yaml"
"$root/usr/bin/tumbled" --config "$root/etc/tumble/tumbled.yaml" --print-config | grep -q '/dev/xsens' ||
  fail "the upgraded tumbled does not read the edited tumbled.yaml"
left=$(cd "$root" && find . -name '*.dpkg-*')
[ -z "$left" ] || fail "the upgrade left $left"

echo "== purge"
in_root --purge tumble
[ -z "$(installed_version)" ] || [ "$(installed_version)" = "unknown ok not-installed " ] ||
  fail "status after purge: $(installed_version)"
# What Debian Policy keeps: the system user (9.2.2: packages do not remove
# users), i.e. the account files systemd-sysusers wrote, their backups and
# the lock file of the shadow suite (present on every Debian system).
left=$(files_outside_dpkg | grep -v -x -E '\./etc/((passwd|group|shadow|gshadow)-?|\.pwd\.lock)' || true)
[ -z "$left" ] || fail "left after purge: $left"
[ ! -e "$root/etc/tumble" ] || fail "/etc/tumble left after purge"
echo "install, unit check, --print-config, upgrade keeping the edited conffile, purge: ok"
