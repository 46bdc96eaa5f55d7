#!/usr/bin/env bash
# Measures tumbled's latencies live, as on the robot: tumble-sim streams a
# scenario in real time (lidar to 127.0.0.1, IMU bytes into a pty) and
# tumbled runs live against them, publishing on memq:// (nothing leaves the
# process). At the end tumbled logs the run's latencies: IMU bytes read ->
# TUMBLE_ODOM and scan complete -> TUMBLE_POSE, p50/p99/max; this script adds
# tumbled's peak resident memory.
#   tools/live_latency.sh BUILD_DIR [SCENARIO] [tumbled options, e.g. --set daemon.realtime_priority=50]
# The figures depend on the machine's load: the simulator itself needs about
# a core to ray-cast in real time.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 BUILD_DIR [SCENARIO] [tumbled options]" >&2; exit 2; }
build=$(readlink -f "$1"); shift
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
scenario=$root/tools/sim/scenarios/default.yaml
if [ $# -ge 1 ] && [ "${1#-}" = "$1" ]; then scenario=$1; shift; fi
sim=$build/tools/sim/tumble-sim
tumbled=$build/daemon/tumbled
for tool in "$sim" "$tumbled"; do
  [ -x "$tool" ] || { echo "missing $tool: build first (./tumble build)" >&2; exit 1; }
done

work=$(mktemp -d)
sim_pid="" tumbled_pid=""
cleanup() {
  for pid in $tumbled_pid $sim_pid; do kill "$pid" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT

"$sim" live "$scenario" --host 127.0.0.1 >"$work/sim.out" 2>"$work/sim.err" &
sim_pid=$!
pty=""
for _ in $(seq 100); do
  pty=$(sed -n 's/^imu-pty //p' "$work/sim.out")
  [ -n "$pty" ] && break
  sleep 0.1
done
[ -n "$pty" ] || { echo "tumble-sim printed no pty:" >&2; cat "$work/sim.err" >&2; exit 1; }

# The scenario's IMU mounting, as the robot's tumbled.yaml would give it.
field() { sed -n "s/^  T_LI: {.*$1: \(\[[^]]*\]\).*/\1/p" "$scenario"; }
mounting=()
translation=$(field translation_m) rotation=$(field rpy_deg)
[ -n "$translation" ] && mounting+=(--set "imu.extrinsic_T_LI.translation_m=$translation")
[ -n "$rotation" ] && mounting+=(--set "imu.extrinsic_T_LI.rotation_rpy_deg=$rotation")

"$tumbled" --lcm-url memq:// --set "imu.device=$pty" --set imu.configure=false \
  --set lidar.bind_address=127.0.0.1 --set lidar.clock=synced "${mounting[@]}" "$@" 2>"$work/tumbled.err" &
tumbled_pid=$!
wait "$sim_pid" || { echo "tumble-sim failed:" >&2; cat "$work/sim.err" >&2; exit 1; }
sim_pid=""
sleep 1
peak_rss=$(sed -n 's/^VmHWM:\s*//p' "/proc/$tumbled_pid/status")
kill -TERM "$tumbled_pid"
wait "$tumbled_pid" || { echo "tumbled failed:" >&2; cat "$work/tumbled.err" >&2; exit 1; }
tumbled_pid=""
grep -E "warn|error|latency over the run" "$work/tumbled.err" | sed 's/^\[[^]]*\] //'
echo "tumbled peak RSS: $peak_rss"
