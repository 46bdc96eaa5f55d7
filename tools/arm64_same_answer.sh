#!/usr/bin/env bash
# Whether the arm64 tumbled gives the amd64 answer: replays the
# default demo run (tools/sim/scenarios/default.yaml, made by the amd64
# tumble-sim) at --rate max through the amd64 tumbled and through the arm64
# one under qemu-user, scores both against ground truth with tumble-eval, and
# fails when their final errors differ by more than 0.01 cm/m. It also says
# whether the trajectories are bit-identical and, if not, by how much the
# positions differ. Takes minutes: the arm64 replay runs emulated.
#   tools/arm64_same_answer.sh AMD64_BUILD ARM64 [OUT_DIR]
# AMD64_BUILD: a native tree (build/release). ARM64: an arm64 tree
# (build/arm64), an arm64 tumbled, or a tumble_<version>_arm64.deb (its
# tumbled is unpacked and run). OUT_DIR: default AMD64_BUILD/arm64-check.
set -euo pipefail
[ $# -ge 2 ] && [ $# -le 3 ] || { sed -n '9,12p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
amd64=$(readlink -f "$1")
arm64=$(readlink -f "$2")
out=$(readlink -m "${3:-$amd64/arm64-check}")
sim=$amd64/tools/sim/tumble-sim
eval=$amd64/tools/eval/tumble-eval
scenario=$root/tools/sim/scenarios/default.yaml
run=$out/default-run
# liblcm1 and libyaml-cpp for arm64 cannot be installed beside the amd64 ones:
# ./tumble unpacks them here (docs/decisions/build.md).
arm64_deps=$root/build/arm64-deps/usr/lib/aarch64-linux-gnu

log() { printf '\033[1m[arm64-check]\033[0m %s\n' "$*" >&2; }
fail() { log "$*"; exit 1; }
# shellcheck source=tools/default_run.sh
source "$root/tools/default_run.sh"

for tool in "$sim" "$eval" "$amd64/daemon/tumbled"; do
  [ -x "$tool" ] || fail "missing $tool: build the amd64 tree first (./tumble build)"
done
command -v qemu-aarch64 >/dev/null || fail "qemu-aarch64 missing (apt install qemu-user)"
[ -d "$arm64_deps" ] || fail "missing $arm64_deps: ./tumble deb (or ./tumble test) unpacks it"
mkdir -p "$out"

case "$arm64" in
  *.deb)
    rm -rf "$out/arm64-root"
    dpkg-deb -x "$arm64" "$out/arm64-root"
    arm64_tumbled=$out/arm64-root/usr/bin/tumbled ;;
  *) arm64_tumbled=$arm64; [ -d "$arm64" ] && arm64_tumbled=$arm64/daemon/tumbled ;;
esac
[ -x "$arm64_tumbled" ] || fail "no arm64 tumbled at $arm64_tumbled"
# ELF e_machine (offset 18, little-endian) 0xb7 = EM_AARCH64.
[ "$(od -An -tx1 -j18 -N2 "$arm64_tumbled" | tr -d ' ')" = b700 ] || fail "$arm64_tumbled is not an arm64 program"

ensure_default_run "$sim" "$scenario" "$run" log
# As ./tumble demo replays it: the simulated IMU's mounting from the manifest.
mounting_of "$run"
replay=(--replay "$run/lidar.pcap" "$run/imu.pcap" --rate max --lcm-url memq:// --log-level warn "${mounting[@]}")

declare -A seconds
for arch in amd64 arm64; do
  start=$SECONDS
  if [ $arch = amd64 ]; then
    log "replaying through $amd64/daemon/tumbled"
    "$amd64/daemon/tumbled" "${replay[@]}" --trajectory-out "$out/$arch.tum" 2>"$out/$arch.log"
  else
    log "replaying through $arm64_tumbled under qemu-aarch64 (a few minutes)"
    # -L /: the loader of libc6:arm64, the glibc build the libraries find (docs/decisions/build.md).
    qemu-aarch64 -L / -E "LD_LIBRARY_PATH=$arm64_deps" "$arm64_tumbled" "${replay[@]}" \
      --trajectory-out "$out/$arch.tum" 2>"$out/$arch.log"
  fi
  seconds[$arch]=$((SECONDS - start))
done

# The final translation error in cm/m, from tumble-eval score's report.
final_cm_per_m() {
  "$eval" score "$run/ground_truth.tum" "$1" | sed -n 's/^- final pose: .*→ \*\*\([0-9.]*\) cm\/m\*\*.*/\1/p'
}
amd64_err=$(final_cm_per_m "$out/amd64.tum")
arm64_err=$(final_cm_per_m "$out/arm64.tum")
[ -n "$amd64_err" ] && [ -n "$arm64_err" ] || fail "tumble-eval score printed no final error"

echo "final error: amd64 $amd64_err cm/m (replay ${seconds[amd64]} s), arm64 $arm64_err cm/m (replay ${seconds[arm64]} s under qemu)"
if cmp -s "$out/amd64.tum" "$out/arm64.tum"; then
  echo "trajectories: bit-identical ($(grep -vc '^#' "$out/amd64.tum") poses)"
else
  # TUM rows: t x y z qx qy qz qw, matched by row (both have one per registered scan).
  awk 'NR == FNR { if ($1 !~ /^#/) a[++n] = $0; next }
       $1 !~ /^#/ { split(a[++m], p); d = sqrt(($2 - p[2])^2 + ($3 - p[3])^2 + ($4 - p[4])^2)
                    if (d > max) max = d; if (d > 0 && !first) first = $1 }
       END { printf "trajectories: differ (%d and %d poses); first differing pose at t = %s s, largest position difference %.3g m\n", n, m, first, max }' \
    "$out/amd64.tum" "$out/arm64.tum"
fi
awk -v a="$amd64_err" -v b="$arm64_err" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 0.01 + 1e-9) }' ||
  fail "the final errors differ by more than 0.01 cm/m"
echo "same answer: the final errors agree within 0.01 cm/m"
