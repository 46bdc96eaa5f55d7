#!/bin/bash
# The fault x run table: rewrites bench runs with one fault each
# (tumble-sim faults, seed 1), replays the clean and the faulted recordings
# through tumbled at --rate max and scores the final pose error with
# tumble-eval. Prints CSV: run,fault,final_cm_per_m,warnings (log lines at
# warning level). Not part of CI: ~20 replays a minute at best.
#
#   tools/fault_matrix.sh BENCH_DIR OUT_DIR [RUN...]     (default runs: cage-01 cage-02 cage-03)
#   TUMBLED, TUMBLE_SIM, TUMBLE_EVAL: the binaries (default: build/release's)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
[ $# -ge 2 ] || { echo "usage: tools/fault_matrix.sh BENCH_DIR OUT_DIR [RUN...]" >&2; exit 2; }
bench=$1 out=$2
shift 2
runs=("$@")
[ ${#runs[@]} -gt 0 ] || runs=(cage-01 cage-02 cage-03)
tumbled=${TUMBLED:-$root/build/release/daemon/tumbled}
sim=${TUMBLE_SIM:-$root/build/release/tools/sim/tumble-sim}
eval_=${TUMBLE_EVAL:-$root/build/release/tools/eval/tumble-eval}
declare -A faults=(
  [clean]=""
  [dup-2%]="--dup-lidar 0.02"
  [swap-2%]="--swap-lidar 0.02"
  [loss-5%]="--drop-lidar 0.05"
  [garbage-5%]="--imu-garbage 0.05"
  [clock-jump+5s]="--lidar-clock-jump 4,5"
  [foreign-5%]="--foreign-lidar 0.05"
)
order=(clean dup-2% swap-2% loss-5% garbage-5% clock-jump+5s foreign-5%)
mkdir -p "$out"
echo "run,fault,final_cm_per_m,warnings"
for run in "${runs[@]}"; do
  [ -f "$bench/$run/lidar.pcap" ] || { echo "fault_matrix: no $bench/$run/lidar.pcap" >&2; exit 2; }
  for fault in "${order[@]}"; do
    dir=$bench/$run
    if [ -n "${faults[$fault]}" ]; then
      dir=$out/$run-$fault
      # shellcheck disable=SC2086
      "$sim" faults "$bench/$run" "$dir" --seed 1 ${faults[$fault]} 2>/dev/null
    fi
    base=$out/$run-$fault
    "$tumbled" --replay "$dir/lidar.pcap" "$dir/imu.pcap" --rate max --lcm-url memq:// \
      --trajectory-out "$base.tum" > "$base.log" 2>&1
    final=$("$eval_" score "$dir/ground_truth.tum" "$base.tum" | sed -n 's/.*final pose: .*→ \*\*\([0-9.]*\) cm\/m\*\*.*/\1/p')
    echo "$run,$fault,$final,$(grep -c '\[warning\]' "$base.log" || true)"
  done
done
