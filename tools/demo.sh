#!/usr/bin/env bash
# What `./tumble demo` runs once the build is done: generates (or reuses) the
# default simulated extreme-motion run with tumble-sim, replays it through
# tumbled (the real RS-16 and MTi decoders, the whole pipeline, publishing on
# LCM as configured), then scores the trajectory against the simulator's
# ground truth and prints the time per stage (its plots in
# BUILD_DIR/demo/out/plots). Meanwhile tumble-view shows the
# run in a browser (its address is printed; TUMBLE_VIEW_LISTEN, default
# 127.0.0.1:8076) and stays up TUMBLE_VIEW_HOLD_S (default 60) seconds after
# it, or until Ctrl-C; TUMBLE_VIEW_HOLD_S=0 stops it with the run.
#   tools/demo.sh BUILD_DIR [tumbled options, e.g. --rate max --model VTW --no-deskew]
# The replay runs at real time unless --rate is given, so lcm-spy and the
# page show the channels at the sensors' rates.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 BUILD_DIR [tumbled options]" >&2; exit 2; }
build=$(readlink -f "$1"); shift
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
sim=$build/tools/sim/tumble-sim
tumbled=$build/daemon/tumbled
eval=$build/tools/eval/tumble-eval
view=$build/tools/view/tumble-view
view_listen=${TUMBLE_VIEW_LISTEN:-127.0.0.1:8076}
view_hold_s=${TUMBLE_VIEW_HOLD_S:-60}
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

# tumble-view beside the replay; the demo goes on without it if it cannot start.
view_pid=
stop_view() { [ -z "$view_pid" ] || { kill "$view_pid" 2>/dev/null; wait "$view_pid" 2>/dev/null || true; }; }
trap stop_view EXIT
if [ -x "$view" ]; then
  "$view" --listen "$view_listen" >"$out/view.out" 2>"$out/view.err" &
  view_pid=$!
  for _ in $(seq 50); do grep -q 'open http' "$out/view.out" 2>/dev/null && break; sleep 0.1; done
  if address=$(grep -o 'http://[^ ]*' "$out/view.out" 2>/dev/null); then
    log "watch it live in a browser: $address"
  else
    log "tumble-view did not start ($(tail -1 "$out/view.err" 2>/dev/null)): no live page"
    view_pid=
  fi
fi

log "replaying through tumbled ${rate[*]} $*; watch it with: $build/lcmtypes/tumble-spy"
"$tumbled" --replay "$run/lidar.pcap" "$run/imu.pcap" "${rate[@]}" "${mounting[@]}" \
  --set lcm.publish_scan=true --set lcm.publish_map_period_s=1 \
  --trajectory-out "$out/trajectory.tum" --scan-log "$out/scans.csv" "$@"

echo
"$eval" score "$run/ground_truth.tum" "$out/trajectory.tum" --scan-log "$out/scans.csv" --plots "$out/plots"
echo
log "trajectory (TUM, for evo): $out/trajectory.tum; per-scan log: $out/scans.csv"
if [ -n "$view_pid" ] && [ "$view_hold_s" -gt 0 ]; then
  log "the page ($address) shows the end of the run for ${view_hold_s} s more (Ctrl-C stops it)"
  sleep "$view_hold_s" || true
fi
