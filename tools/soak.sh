#!/usr/bin/env bash
# The soak: tumbled live for ten minutes (tools/sim/scenarios/
# soak.yaml, the long run's out-and-back twelve times over) against
# tumble-sim live, with its resident memory sampled every 10 s. Prints the
# peak RSS, the RSS slope after the first two minutes (the local map and the
# rings fill up by then; a leak shows as a steady rise), the state changes
# tumbled logged, its final status line (drops), and how late the simulator
# itself ran. Not in CI: it takes the scenario's ten minutes and about two
# cores (the simulator ray-casts in real time).
#   tools/soak.sh BUILD_DIR [SCENARIO] [tumbled options]
set -euo pipefail
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
# shellcheck source=tools/live_session.sh
. "$root/tools/live_session.sh"
begin_live_session "$root/tools/sim/scenarios/soak.yaml" "$@"
start=$(date +%s)
while kill -0 "$sim_pid" 2>/dev/null; do
  rss_kb=$(sed -n 's/^VmRSS:\s*\([0-9]*\) kB/\1/p' "/proc/$tumbled_pid/status" 2>/dev/null || true)
  [ -n "$rss_kb" ] && echo "$(( $(date +%s) - start )) $rss_kb" >> "$work/rss.txt"
  sleep 10
done
stop_tumbled
echo "tumbled peak RSS: $peak_rss"
awk '$1 >= 120 { n++; sx += $1; sy += $2; sxx += $1 * $1; sxy += $1 * $2 }
     END { if (n < 3) { print "RSS slope: too short a run"; exit }
           slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
           printf "RSS after 2 min: %d samples, %.1f to %.1f MiB, slope %+.3f MiB/min\n",
                  n, first / 1024, last / 1024, slope * 60 / 1024 }
     $1 >= 120 { if (!first) first = $2; last = $2 }' "$work/rss.txt"
# The map fills until the robot has seen the whole scene: the second half's
# slope is the one a leak would show.
awk '{ t[NR] = $1; r[NR] = $2 } END { for (i = 1; i <= NR; i++) if (t[i] >= t[NR] / 2) {
       n++; sx += t[i]; sy += r[i]; sxx += t[i] * t[i]; sxy += t[i] * r[i] }
     if (n < 3) { print "RSS slope, second half: too short a run"; exit }
     printf "RSS slope, second half (%d samples from %d s): %+.3f MiB/min\n", n, t[NR] / 2,
            (n * sxy - sx * sy) / (n * sxx - sx * sx) * 60 / 1024 }' "$work/rss.txt"
echo "RSS per minute (MiB): $(awk '$1 % 60 < 10 { printf "%.0f ", $2 / 1024 }' "$work/rss.txt")"
echo "state changes:"
grep -E "state [a-z_]+( -> [a-z_]+)?: " "$work/tumbled.err" | sed 's/^\[[^]]*\] /  /' || echo "  none"
grep -E "final status|latency over the run" "$work/tumbled.err" | sed 's/^\[[^]]*\] //'
sed -n 's/^tumble-sim live: /simulator: /p' "$work/sim.err"
