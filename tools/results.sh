#!/usr/bin/env bash
# Makes docs/results.md and its plots again: every evaluation into its own
# folder of OUT_DIR, then the page from those folders (tools/results_page.sh).
# Not in CI: about two hours on 2 cores.
#
#   tools/results.sh BUILD_DIR DATA_DIR OUT_DIR
#   e.g. tools/results.sh build/release ~/tumble-data /tmp/results
#
# DATA_DIR holds the two simulated benches, bench1 and bench2; whichever is
# missing is made first with tumble-sim (bench1: `tumble-sim bench --seed 1`,
# bench2: the same with --realistic; a few minutes each, 0.6 and 1.8 GB).
# A step whose folder in OUT_DIR is finished (it holds .done) is not run
# again, so an interrupted run goes on where it stopped; remove a folder to
# make it again.
set -euo pipefail
[[ $# -eq 3 ]] || { echo "usage: $0 BUILD_DIR DATA_DIR OUT_DIR" >&2; exit 2; }
build=$(readlink -f "$1") data=$2 out=$(mkdir -p "$3" && readlink -f "$3")
root=$(cd "$(dirname "$(readlink -f "$0")")/.." && pwd)
sim=$build/tools/sim/tumble-sim eval=$build/tools/eval/tumble-eval tumbled=$build/daemon/tumbled
calib=$build/tools/calib/tumble-calib benches=$build/test/bench
for tool in "$sim" "$eval" "$tumbled" "$calib" "$benches/bench_core_registration"; do
  [[ -x $tool ]] || { echo "missing $tool: build first (./tumble build)" >&2; exit 1; }
done
mkdir -p "$data"
# The tree the figures come from: the first run's, when an interrupted one goes on.
[[ -f $out/commit ]] || git -C "$root" describe --always --dirty >"$out/commit" 2>/dev/null || echo "an unversioned tree" >"$out/commit"
log() { printf '\033[1m[results]\033[0m %s\n' "$*" >&2; }

make_bench() {  # make_bench NAME [tumble-sim bench options]
  local name=$1
  shift
  [[ -f $data/$name/bench.csv ]] && return 0
  [[ ! -e $data/$name ]] || { echo "$data/$name exists without bench.csv (an interrupted tumble-sim bench?): remove it" >&2; exit 1; }
  log "making $data/$name (tumble-sim bench $*)"
  nice "$sim" bench --seed 1 --jobs 2 --out "$data/$name.partial" "$@"
  mv "$data/$name.partial" "$data/$name"
}

step() {  # step NAME WHAT COMMAND...: runs COMMAND with $dir, the step's folder
  local name=$1 what=$2
  shift 2
  dir=$out/$name
  [[ -f $dir/.done ]] && { log "$what: done before, in $dir"; return 0; }
  log "$what"
  rm -rf "$dir" && mkdir -p "$dir"
  "$@"
  touch "$dir/.done"
}

make_bench bench1
make_bench bench2 --realistic

matrix() { "$eval" matrix "$@" --tumbled "$tumbled" --out "$dir" >/dev/null; }
gvtw_with_integrity() {  # gvtw_with_integrity BENCH "KIND..." [matrix options]
  local bench=$1 kinds
  read -ra kinds <<<"$2"
  shift 2
  matrix "$bench" --models GVTW --deskew on --kinds "${kinds[@]}" "$@"
  "$eval" integrity "$bench" "$dir" --kinds "${kinds[@]}" >"$dir/integrity.md"
}
for bench in bench1 bench2; do
  step "$bench-cage" "$bench: the paper's matrix on the 46 cage runs" matrix "$data/$bench" --kinds cage
  step "$bench-gvtw" "$bench: tumbled's default (GVTW, de-skew) on every run but the long ones, and its integrity" \
    gvtw_with_integrity "$data/$bench" "rail turntable cage people"
done
step bench2-long "bench2: the long runs, RPE over 10 m, and their integrity" \
  gvtw_with_integrity "$data/bench2" long --segment-m 10

speed() { "$eval" speed "$data/bench1" --kinds cage --runs 'cage-0[1-6]' --tumbled "$tumbled" --out "$dir" >/dev/null; }
step speed "speed: cage-01..06 of bench1, one pass" speed

faults() { "$root/tools/fault_table.sh" "$build" "$dir/runs" "$data"/bench2/cage-0{1,2,3} >"$dir/faults.md"; }
step faults "the sensor faults on bench2's cage-01..03" faults

demo() {
  TUMBLE_VIEW_HOLD_S=0 "$root/tools/demo.sh" "$build" --rate max --log-level warn >"$dir/demo.md" 2>/dev/null
  cp -r "$build/demo/out/plots" "$dir/plots"
}
step demo "the default run (./tumble demo --rate max)" demo

calibration() { "$calib" "$data/bench1" --jobs 2 --out "$dir" >"$dir/calib.out"; }
step calib "the speed-uncertainty fit on bench1 (tumble-calib)" calibration

benchmarks() {
  local aggregates=(--benchmark_repetitions=3 --benchmark_report_aggregates_only=true)
  "$benches/bench_core_registration" --benchmark_filter=GVTW "${aggregates[@]}" >"$dir/registration.txt" 2>/dev/null
  "$benches/bench_rs16" "${aggregates[@]}" >"$dir/rs16.txt" 2>/dev/null
  "$benches/bench_mti" "${aggregates[@]}" >"$dir/mti.txt" 2>/dev/null
}
step benchmarks "the microbenchmarks: a scan's registration, RS-16 and MTi decoding" benchmarks

live_latency() { "$root/tools/live_latency.sh" "$build" >"$dir/latency.txt" 2>/dev/null; }
step live "live latency: tumble-sim live -> tumbled" live_latency

soak() { "$root/tools/soak.sh" "$build" >"$dir/soak.txt" 2>/dev/null; }
step soak "memory: ten minutes live" soak

"$root/tools/results_page.sh" "$out" "$root/docs"
log "wrote $root/docs/results.md and its plots in $root/docs/results/"
