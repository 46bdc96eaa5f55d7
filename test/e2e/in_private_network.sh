#!/bin/sh
# Runs a command inside a private network namespace with only a loopback that
# carries multicast (LCM's udpm), so a test's traffic never leaves it:
#   in_private_network.sh COMMAND [ARGS...]
# Exits 77 (ctest: skipped) where unprivileged namespaces are not allowed.
if ! unshare -rn true 2>/dev/null; then
  echo "SKIP: unshare -rn is not permitted here (unprivileged user namespaces disabled?)" >&2
  exit 77
fi
if ! command -v ip >/dev/null; then
  echo "SKIP: ip (iproute2) is not installed" >&2
  exit 77
fi
exec unshare -rn sh -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$@"' sh "$@"
