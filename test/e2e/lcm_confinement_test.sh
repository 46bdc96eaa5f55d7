#!/bin/sh
# How far tumbled's LCM traffic reaches (docs/security.md), measured: in a
# private network namespace, a second "host" (its own network namespace, a
# veth link away) listens on LCM's group with lcm-logger while tumbled
# publishes TUMBLE_STATUS (5 a second, no sensors needed) under each
# confinement. Fails if a confinement lets a message through, or if the
# unconfined case (the control) does not reach the other host.
#   lcm_confinement_test.sh TUMBLED
# Exits 77 (ctest: skipped) where unprivileged namespaces are not allowed.
set -u
tumbled=$1
group=239.255.76.67
port=7667
if [ -z "${TUMBLE_IN_PRIVATE_NETWORK:-}" ]; then
  if ! unshare -rn true 2>/dev/null; then
    echo "SKIP: unshare -rn is not permitted here (unprivileged user namespaces disabled?)" >&2
    exit 77
  fi
  for tool in ip nsenter lcm-logger; do
    command -v $tool >/dev/null || { echo "SKIP: $tool is not installed" >&2; exit 77; }
  done
  exec unshare -rn env TUMBLE_IN_PRIVATE_NETWORK=1 sh "$0" "$@"
fi
set -e
work=$(mktemp -d)
remote=
cleanup() {
  [ -z "$remote" ] || kill "$remote" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# This host: 10.99.0.1 on veth0, multicast routed out of it (as a robot's
# computer with its network on one interface). The other host: 10.99.0.2.
ip link set lo up
ip link add veth0 type veth peer name veth1
unshare -n sleep 600 &
remote=$!
sleep 0.2
ip link set veth1 netns "$remote"
ip addr add 10.99.0.1/24 dev veth0
ip link set veth0 up
ip route add 224.0.0.0/4 dev veth0
nsenter -t "$remote" -n sh -c 'ip link set lo up && ip addr add 10.99.0.2/24 dev veth1 &&
  ip link set veth1 up && ip route add 224.0.0.0/4 dev veth1'

# status_seen_by_the_other_host URL: the TUMBLE_STATUS messages the other
# host logged while tumbled ran 2 s publishing on URL.
status_seen_by_the_other_host() {
  log=$work/remote.lcmlog
  rm -f "$log"
  nsenter -t "$remote" -n lcm-logger -f --lcm-url="udpm://$group:$port?ttl=1" "$log" >"$work/logger.out" 2>&1 &
  logger=$!
  sleep 0.5
  "$tumbled" --lcm-url "$1" --set daemon.status_period_s=0.2 --set imu.device=/nonexistent/tumble-tty \
    --set lidar.bind_address=127.0.0.1 >"$work/tumbled.out" 2>&1 &
  daemon=$!
  sleep 2
  kill "$daemon"
  wait "$daemon" || true
  sleep 0.3
  kill -INT "$logger"
  wait "$logger" || true
  if [ -f "$log" ]; then grep -a -o TUMBLE_STATUS "$log" | wc -l; else echo 0; fi
}

failed=0
check() {  # check NAME EXPECTATION(none|some) COUNT
  if { [ "$2" = none ] && [ "$3" -eq 0 ]; } || { [ "$2" = some ] && [ "$3" -gt 0 ]; }; then
    echo "ok: $1: $3 TUMBLE_STATUS messages reached the other host"
  else
    echo "FAIL: $1: $3 TUMBLE_STATUS messages reached the other host (expected $2)"
    failed=1
  fi
}

check "ttl=1, the group routed out of veth0 (the control)" some "$(status_seen_by_the_other_host "udpm://$group:$port?ttl=1")"
check "ttl=0" none "$(status_seen_by_the_other_host "udpm://$group:$port?ttl=0")"
# The confinement docs/security.md gives: a host route for the group via lo.
ip route add "$group/32" dev lo
check "ttl=1, a host route for the group via lo" none "$(status_seen_by_the_other_host "udpm://$group:$port?ttl=1")"
ip route del "$group/32" dev lo
exit $failed
