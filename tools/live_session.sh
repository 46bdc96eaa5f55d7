# Sourced by tools/live_latency.sh and tools/soak.sh: tumble-sim streams a
# scenario in real time (lidar to 127.0.0.1, IMU bytes into a pty) and
# tumbled runs live against it, publishing on memq:// (nothing leaves the
# process). Callers call begin_live_session DEFAULT_SCENARIO "$@" (their own
# BUILD_DIR [SCENARIO] [tumbled options]), wait for "$sim_pid" if they like,
# then stop_tumbled. Sets build, scenario, work (a temporary folder, removed
# on exit), sim_pid, tumbled_pid and, after stop_tumbled, peak_rss.
sim_pid="" tumbled_pid=""

begin_live_session() {
  local default_scenario=$1
  shift
  [ $# -ge 1 ] || { echo "usage: $0 BUILD_DIR [SCENARIO] [tumbled options]" >&2; exit 2; }
  build=$(readlink -f "$1")
  shift
  scenario=$default_scenario
  if [ $# -ge 1 ] && [ "${1#-}" = "$1" ]; then scenario=$1; shift; fi
  work=$(mktemp -d)
  trap 'kill_live_session; rm -rf "$work"' EXIT
  start_live_session "$@"
}

kill_live_session() {
  for pid in $tumbled_pid $sim_pid; do kill "$pid" 2>/dev/null || true; done
}

start_live_session() {
  local sim=$build/tools/sim/tumble-sim tumbled=$build/daemon/tumbled tool pty=""
  for tool in "$sim" "$tumbled"; do
    [ -x "$tool" ] || { echo "missing $tool: build first (./tumble build)" >&2; exit 1; }
  done
  "$sim" live "$scenario" --host 127.0.0.1 >"$work/sim.out" 2>"$work/sim.err" &
  sim_pid=$!
  for _ in $(seq 100); do
    pty=$(sed -n 's/^imu-pty //p' "$work/sim.out")
    [ -n "$pty" ] && break
    sleep 0.1
  done
  [ -n "$pty" ] || { echo "tumble-sim printed no pty:" >&2; cat "$work/sim.err" >&2; exit 1; }
  # The scenario's IMU mounting, as the robot's tumbled.yaml would give it.
  field() { sed -n "s/^  T_LI: {.*$1: \(\[[^]]*\]\).*/\1/p" "$scenario"; }
  local mounting=() translation rotation
  translation=$(field translation_m) rotation=$(field rpy_deg)
  [ -n "$translation" ] && mounting+=(--set "imu.extrinsic_T_LI.translation_m=$translation")
  [ -n "$rotation" ] && mounting+=(--set "imu.extrinsic_T_LI.rotation_rpy_deg=$rotation")
  "$tumbled" --lcm-url memq:// --set "imu.device=$pty" --set imu.configure=false \
    --set lidar.bind_address=127.0.0.1 --set lidar.clock=synced "${mounting[@]}" "$@" 2>"$work/tumbled.err" &
  tumbled_pid=$!
}

# Stops tumbled (SIGTERM) once the scenario has played, and fails if either failed.
stop_tumbled() {
  wait "$sim_pid" || { echo "tumble-sim failed:" >&2; cat "$work/sim.err" >&2; exit 1; }
  sim_pid=""
  sleep 1
  peak_rss=$(sed -n 's/^VmHWM:\s*//p' "/proc/$tumbled_pid/status")
  kill -TERM "$tumbled_pid"
  wait "$tumbled_pid" || { echo "tumbled failed:" >&2; cat "$work/tumbled.err" >&2; exit 1; }
  tumbled_pid=""
}
