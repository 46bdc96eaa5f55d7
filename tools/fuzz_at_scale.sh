#!/bin/bash
# Runs every libFuzzer target for at least RUNS executions each (default
# 10 M) from its seeds (test/fuzz/seeds_NAME.txt), then replays the corpus it
# grew through the ASan tree, and prints executions, coverage and crashes per
# fuzzer. Not part of CI.
#
# Two trees, because ASan's allocator maps, poisons and unmaps every large
# buffer (the RS-16 driver reserves 3.7 MB per input): under ASan a fuzzer
# runs ~1.7 k inputs/s, in build/fuzz (libFuzzer + UBSan, -O2) ~8 k/s. The
# 10 M executions run in build/fuzz; every input they kept (the corpus: each
# one new coverage) then runs once more under ASan + UBSan in build/asan,
# which `./tumble test` builds. build/fuzz is configured here when missing.
# Corpora and crash files go to build/fuzz/fuzz_at_scale/NAME/.
#
#   tools/fuzz_at_scale.sh [RUNS] [FUZZER...]     e.g. tools/fuzz_at_scale.sh 10000000 fuzz_rs16
#   FIXTURES=../shared/fixtures (default) finds the fixture seeds.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
runs=${1:-10000000}
shift || true
build=$root/build/fuzz
asan=$root/build/asan
fixtures=${FIXTURES:-$root/../shared/fixtures}
fuzzers=("$@")
if [ ${#fuzzers[@]} -eq 0 ]; then
  for seeds in "$root"/test/fuzz/seeds_*.txt; do name=${seeds##*/seeds_}; fuzzers+=("${name%.txt}"); done
fi

if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1" \
    -DCMAKE_CXX_COMPILER=clang++ -DTUMBLE_SANITIZE=undefined -DTUMBLE_FUZZ=ON -DTUMBLE_BENCH=OFF >/dev/null ||
    { echo "fuzz_at_scale: cannot configure $build" >&2; exit 2; }
fi
cmake --build "$build" --target "${fuzzers[@]}" >/dev/null || { echo "fuzz_at_scale: cannot build $build" >&2; exit 2; }
[ -d "$asan/test/fuzz" ] || echo "fuzz_at_scale: no $asan/test/fuzz (./tumble test builds it): no ASan replay" >&2

seed_list() {  # the seeds file's existing paths, comma-separated
  local list="" line path
  while IFS= read -r line; do
    [ -z "$line" ] && continue
    case $line in repo:*) path=$root/${line#repo:} ;; *) path=$fixtures/$line ;; esac
    [ -e "$path" ] && list=${list:+$list,}$path
  done < "$root/test/fuzz/seeds_$1.txt"
  echo "$list"
}

crash_files() { find "$1" -maxdepth 1 \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l; }

failed=0
printf '%-12s %12s %8s %8s %8s %8s %14s %13s\n' fuzzer executions cov ft crashes seconds asan_replayed asan_crashes
for name in "${fuzzers[@]}"; do
  out=$build/fuzz_at_scale/$name
  mkdir -p "$out/corpus" "$out/asan"
  seeds=$(seed_list "$name")
  options=()  # the fuzzer's own flags (test/fuzz/options_NAME.txt), after the defaults they override
  [ -f "$root/test/fuzz/options_$name.txt" ] && mapfile -t options < "$root/test/fuzz/options_$name.txt"
  start=$(date +%s)
  # -max_len: the RS-16 pcap seeds are whole captures (0.5 MB), of which the
  # fuzz target reads 48 records (62 kB); longer inputs only slow it down.
  "$build/test/fuzz/$name" -runs="$runs" -max_len=65536 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$out/" ${seeds:+-seed_inputs=$seeds} "${options[@]}" "$out/corpus" > "$out/log" 2>&1
  rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$out/log" | tail -1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<< "$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<< "$last")
  crashes=$(crash_files "$out")
  seconds=$(( $(date +%s) - start ))
  replayed="-" asan_crashes="-"
  if [ -x "$asan/test/fuzz/$name" ]; then
    # -runs=0: run each corpus input once, no mutation.
    "$asan/test/fuzz/$name" -runs=0 -timeout=30 -rss_limit_mb=4096 -artifact_prefix="$out/asan/" \
      "$out/corpus" > "$out/asan/log" 2>&1 || rc=$((rc == 0 ? 1 : rc))
    replayed=$(find "$out/corpus" -type f | wc -l)
    asan_crashes=$(crash_files "$out/asan")
  fi
  [ "$rc" -eq 0 ] && [ "$crashes" -eq 0 ] || failed=1
  case $asan_crashes in 0 | -) ;; *) failed=1 ;; esac
  printf '%-12s %12s %8s %8s %8s %8s %14s %13s%s\n' "$name" "${execs:-?}" "${cov:-?}" "${ft:-?}" "$crashes" \
    "$seconds" "$replayed" "$asan_crashes" "$([ $rc -ne 0 ] && echo " (exit $rc, see $out/log, $out/asan/log)")"
done
exit $failed
