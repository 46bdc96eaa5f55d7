#!/usr/bin/env bash
# Issue 15's ablation (README, "Which sources make bench2 hard"): bench2's
# first cage runs remade with each error source alone (the same scenarios and
# seeds, every other switch removed), with all of them (bench2's own bytes),
# and with all of them plus each source bench2 leaves off (imu.vibration,
# lidar.mixed_pixels), each set scored with NM and GVTW, de-skew on. Markdown
# on stdout: cm/m median / Q3 / max and deg/m median per model. Not in CI.
#
#   tools/ablation.sh BUILD_DIR OUT_DIR BENCH2_DIR [CAGES]   (CAGES: 12)
#   e.g. tools/ablation.sh build/release /tmp/ablation /work/data/bench2
# OUT_DIR keeps what it made: runs and scores already there are reused (an
# interrupted ablation resumes); after changing tumble-sim or tumbled, use a
# fresh one.
set -euo pipefail
[[ $# -ge 3 ]] || { echo "usage: $0 BUILD_DIR OUT_DIR BENCH2_DIR [CAGES]" >&2; exit 2; }
build=$1 out=$2 bench=$3 cages=${4:-12}
sim=$build/tools/sim/tumble-sim eval=$build/tools/eval/tumble-eval
mkdir -p "$out"

# The switches of bench2's cage scenarios (lidar:, imu:) and its lidar-IMU offset.
bench_sources=(range_offset_error intensity_range_bias dark_surface_dropout cage_bars
               scale_factor_error misalignment g_sensitivity temperature_drift timestamp_jitter imu_time_offset)
# set name | the one bench2 source kept ("all", "none") | sources bench2 leaves off, turned on
sets=("none|none|")
for s in "${bench_sources[@]}"; do sets+=("$s|$s|"); done
sets+=("all (bench2)|all|" "all + imu.vibration|all|vibration" "all + lidar.mixed_pixels|all|mixed_pixels"
       "imu.vibration alone|none|vibration" "lidar.mixed_pixels alone|none|mixed_pixels")

# scenario FILE KEEP EXTRA: the scenario with bench2's sources other than KEEP
# removed (a switch and its sub-keys; the offset set to 0) and EXTRA switched on.
scenario() {
  awk -v keep="$2" -v extra="$3" -v sources="${bench_sources[*]}" '
    BEGIN { n = split(sources, list, " "); for (i = 1; i <= n; ++i) known[list[i]] = 1 }
    /^[^ ]/ { section = $1; skipping = 0 }
    /^  [^ ]/ {
      key = $1; sub(/:$/, "", key); skipping = 0
      if (section == "extrinsics:" && key == "imu_time_offset_s" && keep != "all" && keep != "imu_time_offset") {
        print "  imu_time_offset_s: 0"; next
      }
      if ((section == "lidar:" || section == "imu:") && (key in known) && keep != "all" && keep != key) {
        skipping = 1; next
      }
    }
    /^   / { if (skipping) next }
    { print }
    (section == "imu:" && $0 == "imu:" && extra == "vibration") { print "  vibration: true" }
    (section == "lidar:" && $0 == "lidar:" && extra == "mixed_pixels") { print "  mixed_pixels: true" }
  ' "$1"
}

# quantile Q FORMAT: type-7 quantile of the sorted numbers on stdin ("–" for none).
quantile() {
  awk -v q="$1" -v format="$2" '{ v[NR] = $1 } END {
    if (NR == 0) { print "–"; exit }
    h = (NR - 1) * q; i = int(h) + 1; j = i < NR ? i + 1 : NR
    printf format, v[i] + (h - int(h)) * (v[j] - v[i]) }'
}

# summary RUNS_CSV MODEL: "median / Q3 / max | deg/m median | diverged" of the de-skewed runs.
summary() {
  local cm deg diverged
  cm=$(awk -F, -v m="$2" '$3 == m && $4 == 1 && $5 == "ok" { print $13 }' "$1" | sort -g)
  deg=$(awk -F, -v m="$2" '$3 == m && $4 == 1 && $5 == "ok" { print $14 }' "$1" | sort -g)
  diverged=$(awk -F, -v m="$2" '$3 == m && $4 == 1 && $5 == "diverged"' "$1" | wc -l)
  echo "$(quantile 0.5 %.2f <<< "$cm") / $(quantile 0.75 %.2f <<< "$cm") / $(quantile 1 %.2f <<< "$cm") |" \
       "$(quantile 0.5 %.3f <<< "$deg") | $diverged"
}

echo "| set | NM cm/m median / Q3 / max | NM deg/m median | NM diverged | GVTW cm/m median / Q3 / max | GVTW deg/m median | GVTW diverged |"
echo "|---|---|---|---|---|---|---|"
for entry in "${sets[@]}"; do
  IFS='|' read -r name keep extra <<< "$entry"
  dir=$out/$(echo "$name" | tr -c 'a-zA-Z0-9\n' '_')
  mkdir -p "$dir"
  head -1 "$bench/bench.csv" > "$dir/bench.csv"
  for i in $(seq -f '%02g' 1 "$cages"); do
    run=cage-$i
    grep "^$run," "$bench/bench.csv" >> "$dir/bench.csv"
    scenario "$bench/$run/scenario.yaml" "$keep" "$extra" > "$dir/$run.yaml"
    [[ -f $dir/$run/lidar.pcap ]] || "$sim" run "$dir/$run.yaml" --out "$dir/$run" > /dev/null
  done
  [[ -f $dir/eval/runs.csv ]] ||
    "$eval" matrix "$dir" --models NM GVTW --deskew on --jobs 2 --out "$dir/eval" > "$dir/eval.log" 2>&1
  echo "| $name | $(summary "$dir/eval/runs.csv" NM) | $(summary "$dir/eval/runs.csv" GVTW) |"
done
