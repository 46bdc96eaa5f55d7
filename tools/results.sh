#!/usr/bin/env bash
# Makes again every table and plot of docs/results.md, each into its own
# folder of OUT_DIR, and prints which file holds which table. Not in CI:
# on 2 cores the two cage matrices take about 20 minutes each, the whole
# script about an hour and a half.
#
#   tools/results.sh BUILD_DIR DATA_DIR OUT_DIR
#   e.g. tools/results.sh build/release ~/tumble-data /tmp/results
#
# DATA_DIR holds the two simulated benches, bench1 and bench2; whichever is
# missing is made first with tumble-sim (bench1: `tumble-sim bench --seed 1`,
# bench2: the same with --realistic; a few minutes each, 0.6 and
# 1.8 GB). The plots docs/results/cage-matrix.png and bench2-cage-matrix.png
# are OUT_DIR/bench1-cage/boxplot.png and OUT_DIR/bench2-cage/boxplot.png.
set -euo pipefail
[[ $# -eq 3 ]] || { echo "usage: $0 BUILD_DIR DATA_DIR OUT_DIR" >&2; exit 2; }
build=$(readlink -f "$1") data=$2 out=$3
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
sim=$build/tools/sim/tumble-sim eval=$build/tools/eval/tumble-eval tumbled=$build/daemon/tumbled
for tool in "$sim" "$eval" "$tumbled"; do
  [[ -x $tool ]] || { echo "missing $tool: build first (./tumble build)" >&2; exit 1; }
done
mkdir -p "$data" "$out"
log() { printf '\033[1m[results]\033[0m %s\n' "$*" >&2; }

make_bench() {  # make_bench NAME [tumble-sim bench options]
  local name=$1
  shift
  [[ -d $data/$name ]] && return 0
  log "making $data/$name (tumble-sim bench $*)"
  nice "$sim" bench --seed 1 --jobs 2 --out "$data/$name" "$@"
}
make_bench bench1
make_bench bench2 --realistic

for bench in bench1 bench2; do
  log "$bench: the paper's matrix on the 46 cage runs"
  "$eval" matrix "$data/$bench" --kinds cage --tumbled "$tumbled" --out "$out/$bench-cage" >/dev/null
  log "$bench: every run with tumbled's default (GVTW, de-skew), then the expected error as a detector"
  "$eval" matrix "$data/$bench" --models GVTW --deskew on --tumbled "$tumbled" --out "$out/$bench-gvtw" >/dev/null
  "$eval" integrity "$data/$bench" "$out/$bench-gvtw" >"$out/$bench-gvtw/integrity.md"
done

log "speed: cage-01..06 of bench1, one pass"
"$eval" speed "$data/bench1" --kinds cage --runs 'cage-0[1-6]' --tumbled "$tumbled" --out "$out/speed" >/dev/null

log "the sensor faults on bench2's cage-01..03"
"$root/tools/fault_table.sh" "$build" "$out/faults" "$data"/bench2/cage-0{1,2,3} >"$out/faults.md"

log "the default run (./tumble demo --rate max)"
"$root/tools/demo.sh" "$build" --rate max --log-level warn >"$out/demo.md" 2>/dev/null

cat <<EOF
docs/results.md's tables, made again:
  cage matrices (bench1, bench2):  $out/bench1-cage/results.md, $out/bench2-cage/results.md
  their plots:                     $out/bench1-cage/boxplot.png, $out/bench2-cage/boxplot.png
  every run, GVTW + de-skew:       $out/bench1-gvtw/results.md, $out/bench2-gvtw/results.md (runs.csv per run)
  the expected error as detector:  $out/bench1-gvtw/integrity.md, $out/bench2-gvtw/integrity.md
  speed:                           $out/speed/speed.md
  sensor faults:                   $out/faults.md
  the default run:                 $out/demo.md
EOF
