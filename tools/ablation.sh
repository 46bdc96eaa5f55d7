#!/usr/bin/env bash
# The ablation of bench2's error sources (docs/decisions/deskew-and-weights.md): bench2's
# first cage runs remade with each error source alone (the same scenarios and
# seeds, every other switch removed), with all of them (bench2's own bytes),
# and with all of them plus each source bench2 leaves off (imu.vibration,
# lidar.mixed_pixels), each set scored with NM and GVTW, de-skew on. Markdown
# on stdout, per model: cm/m median / Q3 / max and deg/m median of the runs
# that did not diverge, and how many diverged or failed. Not in CI.
#
#   tools/ablation.sh BUILD_DIR OUT_DIR BENCH2_DIR [CAGES]   (CAGES: 12)
#   e.g. tools/ablation.sh build/release /tmp/ablation /work/data/bench2
# OUT_DIR keeps what it made: runs and scores already there are reused (an
# interrupted ablation resumes); after changing tumble-sim or tumbled, use a
# fresh one.
set -euo pipefail
export LC_ALL=C  # sort -g and printf read and write numbers with a dot
[[ $# -ge 3 ]] || { echo "usage: $0 BUILD_DIR OUT_DIR BENCH2_DIR [CAGES]" >&2; exit 2; }
build=$1 out=$2 bench=$3 cages=${4:-12}
sim=$build/tools/sim/tumble-sim eval=$build/tools/eval/tumble-eval
mkdir -p "$out"

# The switches of bench2's cage scenarios (lidar:, imu:) and its lidar-IMU offset.
bench_sources=(range_offset_error intensity_range_bias dark_surface_dropout cage_bars
               scale_factor_error misalignment g_sensitivity temperature_drift timestamp_jitter imu_time_offset)
# set name | the one bench2 source kept ("all", "none") | a source bench2 leaves off, turned on
sets=("none|none|")
for s in "${bench_sources[@]}"; do sets+=("$s|$s|"); done
sets+=("all (bench2)|all|" "all + imu.vibration|all|vibration" "all + lidar.mixed_pixels|all|mixed_pixels"
       "imu.vibration alone|none|vibration" "lidar.mixed_pixels alone|none|mixed_pixels")

# scenario FILE KEEP EXTRA: the scenario with bench2's sources other than KEEP
# removed (a switch and its sub-keys; the offset set to 0) and EXTRA switched
# on (vibration in imu:, mixed_pixels in lidar:, replacing any setting of it).
scenario() {
  awk -v keep="$2" -v extra="$3" -v sources="${bench_sources[*]}" '
    BEGIN {
      n = split(sources, list, " "); for (i = 1; i <= n; ++i) known[list[i]] = 1
      if (extra == "vibration") extra_section = "imu:"
      if (extra == "mixed_pixels") extra_section = "lidar:"
    }
    /^[^ ]/ { section = $1; skipping = 0 }
    /^  [^ ]/ {
      key = $1; sub(/:$/, "", key); skipping = 0
      if (section == "extrinsics:" && key == "imu_time_offset_s" && keep != "all" && keep != "imu_time_offset") {
        print "  imu_time_offset_s: 0"; next
      }
      if ((section == "lidar:" || section == "imu:") && (key in known) && keep != "all" && keep != key) {
        skipping = 1; next
      }
      if (section == extra_section && key == extra) { skipping = 1; next }
    }
    /^   / { if (skipping) next }
    { print }
    /^[^ ]/ && section == extra_section { print "  " extra ": true"; added = 1 }
    END { if (extra != "" && !added) { print "no " extra_section " section to turn " extra " on in" > "/dev/stderr"; exit 1 } }
  ' "$1"
}

# quantile Q FORMAT: type-7 quantile of the sorted numbers on stdin ("–" for none).
quantile() {
  awk -v q="$1" -v format="$2" 'NF { v[++n] = $1 } END {
    if (n == 0) { print "–"; exit }
    h = (n - 1) * q; i = int(h) + 1; j = i < n ? i + 1 : n
    printf format, v[i] + (h - int(h)) * (v[j] - v[i]) }'
}

# column RUNS_CSV MODEL STATUS NAME: the de-skewed MODEL runs' NAME column where status is STATUS.
column() {
  awk -F, -v m="$2" -v status="$3" -v name="$4" '
    NR == 1 { for (i = 1; i <= NF; ++i) at[$i] = i; next }
    $at["model"] == m && $at["deskew"] == 1 && $at["status"] == status { print $at[name] }' "$1"
}

# summary RUNS_CSV MODEL: "median / Q3 / max | deg/m median | diverged (failed)".
summary() {
  local cm deg diverged failed
  cm=$(column "$1" "$2" ok translation_cm_per_m | sort -g)
  deg=$(column "$1" "$2" ok rotation_deg_per_m | sort -g)
  diverged=$(column "$1" "$2" diverged run | wc -l)
  failed=$(column "$1" "$2" failed run | wc -l)
  echo "$(quantile 0.5 %.2f <<< "$cm") / $(quantile 0.75 %.2f <<< "$cm") / $(quantile 1 %.2f <<< "$cm") |" \
       "$(quantile 0.5 %.3f <<< "$deg") | $diverged$([[ $failed -eq 0 ]] || echo " ($failed failed)")"
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
    grep "^$run," "$bench/bench.csv" >> "$dir/bench.csv" || { echo "$bench/bench.csv has no $run" >&2; exit 1; }
    scenario "$bench/$run/scenario.yaml" "$keep" "$extra" > "$dir/$run.yaml"
    # manifest.yaml is the last file tumble-sim writes: a run without it was interrupted.
    [[ -f $dir/$run/manifest.yaml ]] || { rm -rf "${dir:?}/$run"; "$sim" run "$dir/$run.yaml" --out "$dir/$run" > /dev/null; }
  done
  if [[ ! -f $dir/eval/runs.csv ]]; then
    # A failed job makes matrix exit 1 but still writes runs.csv (summary counts it).
    "$eval" matrix "$dir" --models NM GVTW --deskew on --jobs 2 --out "$dir/eval" > "$dir/eval.log" 2>&1 ||
      echo "$name: tumble-eval matrix failed, see $dir/eval.log" >&2
  fi
  echo "| $name | $(summary "$dir/eval/runs.csv" NM) | $(summary "$dir/eval/runs.csv" GVTW) |"
done
