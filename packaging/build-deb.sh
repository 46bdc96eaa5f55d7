#!/usr/bin/env bash
# Builds the Debian package from a configured and built tree:
#   packaging/build-deb.sh BUILD_DIR ARCH OUT_DIR [VERSION]
# -> OUT_DIR/tumble_<VERSION>_<ARCH>.deb. VERSION defaults to the CMake
# project's (project(tumble VERSION ...), read from BUILD_DIR's cache).
# The files are what `cmake --install --strip` puts in place (the tree must be
# configured with the prefix /usr);
# runtime dependencies come from dpkg-shlibdeps. A cross tree's unpacked arm64
# packages (TUMBLE_ARM64_DEPS, see cmake/aarch64-linux-gnu.cmake) are given
# to dpkg-shlibdeps with their own shlibs entries, as dpkg does not know them.
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 BUILD_DIR ARCH OUT_DIR [VERSION]" >&2; exit 2; }
here=$(cd "$(dirname "$(readlink -f "$0")")" && pwd)
build=$(readlink -f "$1")
arch=$2
mkdir -p "$3"
out=$(readlink -f "$3")
cache_value() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
version=${4:-$(cache_value CMAKE_PROJECT_VERSION)}
[ -n "$version" ] || { echo "$0: no CMAKE_PROJECT_VERSION in $build/CMakeCache.txt" >&2; exit 1; }
# tumbled compiles in its configuration's path from the configured prefix.
prefix=$(cache_value CMAKE_INSTALL_PREFIX)
[ "$prefix" = /usr ] || {
  echo "$0: $build is configured for the prefix $prefix, where tumbled would look for $prefix/etc/tumble/tumbled.yaml;" \
    "the package needs -DCMAKE_INSTALL_PREFIX=/usr" >&2
  exit 1
}

work=$out/deb-$arch-$version
stage=$work/root
rm -rf "$work"
mkdir -p "$stage/DEBIAN" "$work/debian"
DESTDIR=$stage cmake --install "$build" --prefix /usr --strip >/dev/null

doc=$stage/usr/share/doc/tumble
install -d "$doc"
install -m 644 "$here/copyright" "$doc/copyright"
maintainer=$(sed -n 's/^Maintainer: //p' "$here/control.in")
# The changelog's date: the source's commit (reproducible), else now.
epoch=${SOURCE_DATE_EPOCH:-$(git -C "$here" log -1 --format=%ct 2>/dev/null || date +%s)}
# A native package (no Debian revision): changelog.gz, not changelog.Debian.gz.
printf 'tumble (%s) unstable; urgency=medium\n\n  * tumble %s, built from its CMake project.\n\n -- %s  %s\n' \
  "$version" "$version" "$maintainer" "$(LC_ALL=C date -u -R -d "@$epoch")" | gzip -9n >"$doc/changelog.gz"
# Debian's Java policy: a public jar is NAME-VERSION.jar, NAME.jar links to it
# (tumble-spy uses NAME.jar).
jar=$stage/usr/share/java/tumble-lcmtypes.jar
if [ -f "$jar" ]; then
  mv "$jar" "${jar%.jar}-$version.jar"
  ln -s "tumble-lcmtypes-$version.jar" "$jar"
fi

# Every file under /etc is a conffile: a user's edit survives upgrades.
(cd "$stage" && find etc -type f | sed 's|^|/|' | sort) >"$stage/DEBIAN/conffiles"
install -m 755 "$here/postinst" "$here/prerm" "$here/postrm" "$stage/DEBIAN/"
chmod -R u=rwX,go=rX "$stage"
find "$stage/usr/bin" -type f -exec chmod 755 {} +

# dpkg-shlibdeps reads debian/control and the host architecture from DEB_HOST_ARCH.
printf 'Source: tumble\n\nPackage: tumble\nArchitecture: any\n' >"$work/debian/control"
shlibdeps_args=()
deps=$(cache_value TUMBLE_ARM64_DEPS)
if [ -n "$deps" ]; then
  shlibdeps_args+=("-l$deps/usr/lib/$(dpkg-architecture -a"$arch" -qDEB_HOST_MULTIARCH 2>/dev/null)" "-L$deps/shlibs")
fi
elves=()
for f in "$stage"/usr/bin/*; do
  [ "$(head -c4 "$f" | od -An -c | tr -d ' ')" = '177ELF' ] && elves+=("$f")
done
shlibs=$(cd "$work" && DEB_HOST_ARCH=$arch dpkg-shlibdeps -O "${shlibdeps_args[@]}" "${elves[@]}" 2>"$work/shlibdeps.log") ||
  { cat "$work/shlibdeps.log" >&2; exit 1; }
[ -s "$work/shlibdeps.log" ] && cat "$work/shlibdeps.log" >&2
shlibs=${shlibs#shlibs:Depends=}

size=$(du -sk --exclude=DEBIAN "$stage" | cut -f1)
sed -e "s/@VERSION@/$version/" -e "s/@ARCH@/$arch/" -e "s/@INSTALLED_SIZE@/$size/" \
    -e "s/@SHLIBS_DEPENDS@/$shlibs/" "$here/control.in" >"$stage/DEBIAN/control"

deb=$out/tumble_${version}_${arch}.deb
dpkg-deb --root-owner-group -Zxz --build "$stage" "$deb" >/dev/null
echo "$deb"
