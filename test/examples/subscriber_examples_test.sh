#!/usr/bin/env bash
# One subscriber example against tumbled replaying a simulated run at real
# time over udpm with ttl=0 (run it inside test/e2e/in_private_network.sh):
#   subscriber_examples_test.sh SOURCE_DIR TUMBLED RUN_DIR SUBSCRIBER [ARGS...]
# The subscriber must see the state reach tracking and receive 50 poses it
# trusts before the replay ends; tumbled must log which configuration it read.
set -euo pipefail
src=$1 tumbled=$2 run=$3
shift 3
url='udpm://239.255.76.67:7667?ttl=0'
fail() { echo "FAILED: $*" >&2; exit 1; }
work=$(mktemp -d)
sub=
trap '[ -z "$sub" ] || kill "$sub" 2>/dev/null || true; rm -rf "$work"' EXIT

"$@" --lcm-url "$url" --poses 50 --timeout-s 60 >"$work/subscriber.out" 2>&1 &
sub=$!
for _ in $(seq 100); do
  grep -q '^listening' "$work/subscriber.out" && break
  sleep 0.1
done
grep -q '^listening' "$work/subscriber.out" || fail "the subscriber did not start: $(cat "$work/subscriber.out")"

source "$src/tools/default_run.sh"
mounting_of "$run"
"$tumbled" --replay "$run/lidar.pcap" "$run/imu.pcap" --rate 1 --lcm-url "$url" "${mounting[@]}" \
  >"$work/tumbled.out" 2>&1 || fail "tumbled exited $?: $(tail -5 "$work/tumbled.out")"
rc=0
wait "$sub" || rc=$?
sub=
echo "subscriber (exit $rc), first lines:"
head -5 "$work/subscriber.out"
[ "$rc" -eq 0 ] || fail "the subscriber exited $rc: $(grep -v ' p_W ' "$work/subscriber.out")"
grep -q '^state tracking' "$work/subscriber.out" || fail "the subscriber saw no state tracking"
poses=$(grep -c ' p_W ' "$work/subscriber.out" || true)
[ "$poses" -ge 50 ] || fail "$poses trusted poses printed, not 50"
grep -E -q 'configuration from (compiled defaults|/)' "$work/tumbled.out" ||
  fail "tumbled did not log which configuration it read: $(head -3 "$work/tumbled.out")"
echo "$poses trusted poses; tumbled: $(grep -o 'configuration from .*' "$work/tumbled.out")"
