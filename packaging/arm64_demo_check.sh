#!/usr/bin/env bash
# The same answer on both architectures: the arm64 package's tumbled, run
# under qemu-user, replays the default demo run (tools/demo.sh) and must end
# with the same final error as the native tumbled, within 0.01 cm/m.
#   packaging/arm64_demo_check.sh RELEASE_BUILD_DIR ARM64_DEB ARM64_DEPS_DIR
# ARM64_DEPS_DIR: the unpacked arm64 libraries apt cannot co-install (liblcm1).
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: $0 RELEASE_BUILD_DIR ARM64_DEB ARM64_DEPS_DIR" >&2; exit 2; }
build=$(readlink -f "$1")
deb=$(readlink -f "$2")
deps=$(readlink -f "$3")
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
sim=$build/tools/sim/tumble-sim
scenario=$root/tools/sim/scenarios/default.yaml
run=$build/demo/default-run
out=$build/demo/arm64-check
log() { printf '\033[1m[arm64 check]\033[0m %s\n' "$*" >&2; }

# The run as tools/demo.sh makes it (and reuses it).
if [ ! -f "$run/manifest.yaml" ] || [ "$scenario" -nt "$run/manifest.yaml" ] || [ "$sim" -nt "$run/manifest.yaml" ]; then
  log "generating the default run into $run"
  rm -rf "$run"
  "$sim" run "$scenario" --out "$run"
fi
extrinsic() { sed -n "/^  T_LI:/,/meaning:/s/^    $1: //p" "$run/manifest.yaml"; }
replay_args=(--replay "$run/lidar.pcap" "$run/imu.pcap" --rate max --lcm-url memq:// --log-level warn
             --set "imu.extrinsic_T_LI.translation_m=$(extrinsic translation_m)"
             --set "imu.extrinsic_T_LI.rotation_rpy_deg=$(extrinsic rpy_deg)")

rm -rf "$out"
mkdir -p "$out/package"
dpkg-deb -x "$deb" "$out/package"
log "native tumbled"
start=$(date +%s.%N)
"$build/daemon/tumbled" "${replay_args[@]}" --trajectory-out "$out/amd64.tum" 2>"$out/amd64.log"
native_s=$(echo "$(date +%s.%N) - $start" | bc)
log "$(basename "$deb"): tumbled under qemu-aarch64"
start=$(date +%s.%N)
qemu-aarch64 -L /usr/aarch64-linux-gnu -E "LD_LIBRARY_PATH=$deps/usr/lib/aarch64-linux-gnu" \
  "$out/package/usr/bin/tumbled" "${replay_args[@]}" --trajectory-out "$out/arm64.tum" 2>"$out/arm64.log"
emulated_s=$(echo "$(date +%s.%N) - $start" | bc)

# cm/m from the final error in cm and the distance travelled (more digits
# than the score's rounded cm/m).
cm_per_m() {
  "$build/tools/eval/tumble-eval" score "$run/ground_truth.tum" "$1" |
    sed -n 's/.*(\([0-9]*\) poses, .*, \([0-9.]*\) m travelled.*/\2/p; s/^- final pose: \([0-9.]*\) cm.*/\1/p' |
    paste -sd' ' | awk '{ printf "%.4f", $2 / $1 }'
}
native=$(cm_per_m "$out/amd64.tum")
emulated=$(cm_per_m "$out/arm64.tum")
# The largest position difference between the two trajectories, pose by pose.
max_diff_mm=$(paste -d' ' "$out/amd64.tum" "$out/arm64.tum" | awk '
  $1 !~ /^#/ { d = sqrt(($2-$10)^2 + ($3-$11)^2 + ($4-$12)^2) * 1000; if (d > m) m = d; n++ }
  END { printf "%.4f", m }')
identical=no
cmp -s "$out/amd64.tum" "$out/arm64.tum" && identical=yes
echo "final error: amd64 $native cm/m, arm64 (qemu) $emulated cm/m; bit-identical trajectories: $identical;" \
     "largest position difference $max_diff_mm mm over $(grep -vc '^#' "$out/amd64.tum") poses;" \
     "replay took ${native_s%.*} s native, ${emulated_s%.*} s under qemu"
awk -v a="$native" -v b="$emulated" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 0.01) }' ||
  { log "FAILED: the final errors differ by more than 0.01 cm/m"; exit 1; }
