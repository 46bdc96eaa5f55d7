#!/bin/bash
# Runs every libFuzzer target of the ASan tree (build/asan, as `./tumble test`
# configures it) for at least RUNS executions each (default 10 M) from its
# seeds (test/fuzz/seeds_NAME.txt), one after the other, and prints
# executions, coverage and crashes per fuzzer. Not part of CI: at a few
# thousand executions a second this takes hours. Corpora and crash files go
# to build/asan/fuzz_at_scale/NAME/.
#
#   tools/fuzz_at_scale.sh [RUNS] [FUZZER...]     e.g. tools/fuzz_at_scale.sh 10000000 fuzz_rs16
#   FIXTURES=../shared/fixtures (default) finds the fixture seeds.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
runs=${1:-10000000}
shift || true
build=$root/build/asan
fixtures=${FIXTURES:-$root/../shared/fixtures}
[ -d "$build/test/fuzz" ] || { echo "fuzz_at_scale: no $build/test/fuzz (configure build/asan with -DTUMBLE_FUZZ=ON)" >&2; exit 2; }
fuzzers=("$@")
if [ ${#fuzzers[@]} -eq 0 ]; then
  for f in "$build"/test/fuzz/fuzz_*; do [ -x "$f" ] && [ -f "$f" ] && fuzzers+=("$(basename "$f")"); done
fi

seed_list() {  # the seeds file's existing paths, comma-separated
  local list="" line path
  while IFS= read -r line; do
    [ -z "$line" ] && continue
    case $line in repo:*) path=$root/${line#repo:} ;; *) path=$fixtures/$line ;; esac
    [ -e "$path" ] && list=${list:+$list,}$path
  done < "$root/test/fuzz/seeds_$1.txt"
  echo "$list"
}

printf '%-12s %12s %8s %8s %8s %s\n' fuzzer executions cov ft crashes seconds
for name in "${fuzzers[@]}"; do
  out=$build/fuzz_at_scale/$name
  mkdir -p "$out/corpus"
  seeds=$(seed_list "$name")
  start=$(date +%s)
  "$build/test/fuzz/$name" -runs="$runs" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$out/" ${seeds:+-seed_inputs=$seeds} "$out/corpus" > "$out/log" 2>&1
  rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$out/log" | tail -1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<< "$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<< "$last")
  crashes=$(find "$out" -maxdepth 1 \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
  printf '%-12s %12s %8s %8s %8s %s%s\n' "$name" "${execs:-?}" "${cov:-?}" "${ft:-?}" "$crashes" \
    $(( $(date +%s) - start )) "$([ $rc -ne 0 ] && echo " (exit $rc, see $out/log)")"
done
