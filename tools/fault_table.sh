#!/usr/bin/env bash
# The fault x run table (docs/results.md, Sensor faults): each fault class alone
# on each given run folder (tumble-sim run or a bench's cage runs), replayed
# with `tumbled --rate max`, scored against the run's ground truth, with the
# health states and fault warnings tumbled logged. Markdown on stdout. Not in CI.
#
#   tools/fault_table.sh BUILD_DIR OUT_DIR RUN_DIR...
#   e.g. tools/fault_table.sh build/release /tmp/faults /work/data/bench1/cage-0{1,2,3}
set -euo pipefail
[[ $# -ge 3 ]] || { echo "usage: $0 BUILD_DIR OUT_DIR RUN_DIR..." >&2; exit 2; }
build=$1 out=$2
shift 2
sim=$build/tools/sim/tumble-sim tumbled=$build/daemon/tumbled eval=$build/tools/eval/tumble-eval
mkdir -p "$out"

# name|tumble-sim faults options (times in s from the run's first record; the cage rolls from 1.5 s)
faults=(
  "clean|"
  "5 % MSOP lost|--drop-lidar 0.05"
  "2 % MSOP duplicated|--dup-lidar 0.02"
  "2 % MSOP swapped|--swap-lidar 0.02"
  "5 % foreign datagrams|--foreign-lidar 0.05"
  "5 % serial reads with garbage|--imu-garbage 0.05"
  "lidar clock +5 s at 4 s|--lidar-clock-jump 4,5"
  "lidar silent 0.5 s at 4 s|--lidar-gap 4,0.5"
  "lidar restart: silent 3 s at 4 s|--lidar-gap 4,3"
  "IMU silent 0.2 s at 4 s|--imu-gap 4,0.2"
  "IMU silent 1 s at 4 s|--imu-gap 4,1"
  "IMU silent 1 s at 3 s|--imu-gap 3,1"
  "5 % IMU frames with a NaN rate|--imu-nan 0.05"
  "second lidar host from 3 s (its stream 2 s old, 1.5x as fast)|--second-lidar 3,2"
  "motor stalled 2 s at 4 s, lasers firing|--motor-stall 4,2"
  "DIFOP with another calibration from 3 s|--difop-change 3"
)

echo "| fault | run | final error | runaway while good | states and warnings (data time) |"
echo "|---|---|---|---|---|"
for entry in "${faults[@]}"; do
  name=${entry%%|*} options=${entry#*|}
  for run in "$@"; do
    tag=$(basename "$run")-$(echo "$name" | tr -c 'a-zA-Z0-9' '_')
    dir=$out/$tag
    # shellcheck disable=SC2086  # options are words
    "$sim" faults "$run" "$dir" --seed 1 $options > /dev/null
    "$tumbled" --replay "$dir/lidar.pcap" "$dir/imu.pcap" --rate max --lcm-url memq:// \
      --trajectory-out "$dir/trajectory.tum" --scan-log "$dir/scans.csv" > "$dir/tumbled.log" 2>&1 || true
    score=$("$eval" score "$dir/ground_truth.tum" "$dir/trajectory.tum" --scan-log "$dir/scans.csv" 2>&1 || true)
    error=$(echo "$score" | sed -n 's/.*final pose: .*→ \*\*\([0-9.]* cm\/m\)\*\*.*/\1/p' | head -1)
    # The largest rise of the position error within a stretch of good scans (tumble-eval score).
    runaway=$(echo "$score" | sed -n 's/^- \([0-9.]* m\) over .*/\1/p' | head -1)
    # The state changes after start-up (a good-scan count flickering between
    # tracking and degraded left out) and how many warnings named a fault.
    states=$(grep -E 'state [a-z_]+( -> [a-z_]+)?: ' "$dir/tumbled.log" |
             grep -v 'poor scan registration\|registration good again\|IMU and lidar data arriving\|first scan registered' |
             sed -E 's/^.*state ([a-z_]+ -> )?([a-z_]+): (.*) \(data time ([0-9.]+) s\)/\2: \3 at \4 s/' |
             paste -sd ';' | sed 's/;/; /g' || true)
    warnings=$(grep -v 'state ' "$dir/tumbled.log" | grep -c '\[warning\]' || true)
    seen="${states:-no state change}; $warnings other warnings"
    echo "| $name | $(basename "$run") | ${error:-none} | ${runaway:-–} | ${seen:-–} |"
  done
done
