#!/usr/bin/env bash
# What `./tumble demo` runs once the build is done: generates (or reuses) the
# default simulated extreme-motion run with tumble-sim, replays it through
# tumbled (the real RS-16 and MTi decoders, the whole pipeline, publishing on
# LCM as configured), then scores the trajectory against the simulator's
# ground truth and prints the time per stage.
#   tools/demo.sh BUILD_DIR [tumbled options, e.g. --rate max --model VTW --no-deskew]
# The replay runs at real time unless --rate is given, so lcm-spy shows the
# channels at the sensors' rates.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 BUILD_DIR [tumbled options]" >&2; exit 2; }
build=$(readlink -f "$1"); shift
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
sim=$build/tools/sim/tumble-sim
tumbled=$build/daemon/tumbled
eval=$build/tools/eval/tumble-eval
scenario=$root/tools/sim/scenarios/default.yaml
run=$build/demo/default-run
out=$build/demo/out

log() { printf '\033[1m[demo]\033[0m %s\n' "$*" >&2; }
# shellcheck source=tools/default_run.sh
source "$root/tools/default_run.sh"

for tool in "$sim" "$tumbled" "$eval"; do
  [ -x "$tool" ] || { log "missing $tool: build first (./tumble build)"; exit 1; }
done

ensure_default_run "$sim" "$scenario" "$run" log
mounting_of "$run"

rate=(--rate 1)
for arg in "$@"; do [ "$arg" = --rate ] && rate=(); done
mkdir -p "$out"
log "replaying through tumbled ${rate[*]} $*; watch it with: $build/lcmtypes/tumble-spy"
"$tumbled" --replay "$run/lidar.pcap" "$run/imu.pcap" "${rate[@]}" "${mounting[@]}" \
  --trajectory-out "$out/trajectory.tum" --scan-log "$out/scans.csv" "$@"

echo
"$eval" score "$run/ground_truth.tum" "$out/trajectory.tum" --scan-log "$out/scans.csv" --plots "$out/plots"
echo
log "trajectory (TUM, for evo): $out/trajectory.tum; per-scan log: $out/scans.csv"
