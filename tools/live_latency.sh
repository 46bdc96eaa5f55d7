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
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
# shellcheck source=tools/live_session.sh
. "$root/tools/live_session.sh"
begin_live_session "$root/tools/sim/scenarios/default.yaml" "$@"
stop_tumbled
grep -E "warn|error|latency over the run" "$work/tumbled.err" | sed 's/^\[[^]]*\] //'
echo "tumbled peak RSS: $peak_rss"
