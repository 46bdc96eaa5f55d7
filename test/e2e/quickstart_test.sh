#!/bin/bash
# The README's quick start, run as written and in order, against simulated
# sensors: the commands are read from README.md ("Install on a robot", "Quick
# start with real sensors") and docs/robot-setup.md (steps 1 to 9, the ones
# the README leaves out) by doc_steps.awk, so a command that does not work as
# documented fails this test.
#   quickstart_test.sh SOURCE_DIR BUILD_DIR TUMBLE_SIM
#
# The rig: a private network namespace (this host) whose "eth0" is one end of
# a veth link; the other end is the lidar's, 192.168.1.200 in a namespace of
# its own, where `tumble-sim live` sends RS-16 datagrams to 192.168.1.102 (the
# lidar's factory destination) and plays an MTi-30 on a pty. Within it:
#   - sudo is dropped (the namespace's root is this user);
#   - /etc/tumble/ is the DESTDIR install's ($work/root/etc/tumble/),
#     /dev/xsens the simulator's link to its pty, build/release BUILD_DIR,
#     ~ a fresh home, and the installed programs come first on PATH;
#   - tcpdump runs as written when the test runs as root (the namespace is
#     then a network namespace only); in a user namespace it cannot change to
#     its own user, and the test waits for the UDP datagrams it would have
#     printed instead, counted by the kernel, and says so;
#   - commands that need the real host (systemctl, udevadm, adduser,
#     journalctl, systemd-sysusers, sysctl --system, building and copying the
#     package) are not run: the test says so and checks that the files they
#     act on are installed; the service is started as its installed unit's
#     ExecStart= would start it.
# The recorded motion is the first 10 s of handheld_waving.yaml (2 s still,
# then waving): enough for the rotation and the time offset (8 s did not
# determine the rotation), short enough for the calibration to take about a
# minute of CPU.
# Exits 77 (ctest: skipped) where unprivileged namespaces are not allowed or
# a tool is missing.
set -u
source_dir=$(readlink -f "$1")
build_dir=$(readlink -f "$2")
tumble_sim=$(readlink -f "$3")
if [ -z "${TUMBLE_IN_PRIVATE_NETWORK:-}" ]; then
  for tool in ip nsenter tcpdump lcm-logger curl; do
    command -v $tool >/dev/null || { echo "SKIP: $tool is not installed" >&2; exit 77; }
  done
  [ "$(id -u)" -eq 0 ] && exec unshare -n env TUMBLE_IN_PRIVATE_NETWORK=root bash "$0" "$@"
  if ! unshare -rn true 2>/dev/null; then
    echo "SKIP: unshare -rn is not permitted here (unprivileged user namespaces disabled?)" >&2
    exit 77
  fi
  exec unshare -rn env TUMBLE_IN_PRIVATE_NETWORK=user bash "$0" "$@"
fi

here=$(dirname "$(readlink -f "$0")")
work=$(mktemp -d)
destdir=$work/root
export HOME=$work/home
export DESTDIR=$destdir  # cmake --install's staging root
export PATH=$destdir/usr/bin:$PATH
mkdir -p "$HOME" "$work/dev"
cd "$HOME" || exit 1
qs_lidar_ns= qs_sim= qs_sims=0 qs_background=()
cleanup() {
  for pid in "${qs_background[@]}" $qs_sim $qs_lidar_ns; do kill "$pid" 2>/dev/null; done
  wait 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }
say() { printf '\n== %s\n' "$*"; }

# This host and the lidar, one veth link apart; LCM's multicast stays on lo.
ip link set lo up && ip route add 224.0.0.0/4 dev lo || fail "cannot set up lo"
ip link add eth0 type veth peer name lidar0 || fail "cannot make a veth link"
unshare -n sleep 600 &
qs_lidar_ns=$!
sleep 0.2
ip link set lidar0 netns "$qs_lidar_ns" && ip link set eth0 up || fail "cannot move the lidar's end"
nsenter -t "$qs_lidar_ns" -n sh -c 'ip link set lo up && ip addr add 192.168.1.200/24 dev lidar0 &&
  ip link set lidar0 up' || fail "cannot address the lidar"

# start_sim SECONDS [ARGS...]: the simulated sensors, from the lidar's
# namespace; returns once the MTi's /dev/xsens link is there. As root they run
# at a real-time priority: real sensors keep time whatever the host's load,
# and on a loaded machine the simulator at normal priority ran up to a second
# late, a recording no calibration can use.
start_sim() {
  local seconds=$1; shift
  rm -f "$work/dev/xsens"
  qs_sims=$((qs_sims + 1))
  local priority=()
  [ "$TUMBLE_IN_PRIVATE_NETWORK" = root ] && priority=(chrt -f 10)
  nsenter -t "$qs_lidar_ns" -n "${priority[@]}" "$tumble_sim" live "$source_dir/tools/sim/scenarios/handheld_waving.yaml" \
    --host 192.168.1.102 --allow-remote --imu-link "$work/dev/xsens" --duration "$seconds" "$@" \
    >"$work/sim-$qs_sims.out" 2>"$work/sim-$qs_sims.err" &
  qs_sim=$!
  for _ in $(seq 100); do [ -e "$work/dev/xsens" ] && return 0; sleep 0.05; done
  fail "the simulator made no /dev/xsens: $(cat "$work/sim-$qs_sims.err")"
}
stop_sim() {
  [ -z "$qs_sim" ] && return 0
  kill "$qs_sim" 2>/dev/null
  wait "$qs_sim" 2>/dev/null
  qs_sim=
}

# The documented command as it runs here (see the top of this file).
as_here() {
  local c=$1
  c=${c//sudo /}
  c=${c//\/etc\/tumble\//$destdir/etc/tumble/}
  c=${c//\/dev\/xsens/$work/dev/xsens}
  c=${c//build\/release/$build_dir}
  printf '%s' "$c"
}

# host_only COMMAND: true (and says so, and checks the files the command acts
# on) when the command needs the real host, or builds and copies the package
# (test/package/deb_install_test.sh installs it in a throwaway root).
host_only() {
  local c=${1//sudo /} part host=1 why="needs the real host"
  while read -r part; do
    case $part in
      ./tumble\ deb* | scp* | ssh*) why="builds or copies the package: the package test installs it" ;;
      systemctl*) [ -f "$destdir/usr/lib/systemd/system/tumbled.service" ] || fail "no unit tumbled.service installed" ;;
      udevadm*) grep -q 'SYMLINK+="xsens"' "$destdir/usr/lib/udev/rules.d/99-tumble-mti.rules" ||
          fail "no udev rule naming /dev/xsens installed" ;;
      adduser*dialout*) getent group dialout >/dev/null || fail "this host has no group dialout" ;;
      systemd-sysusers*) grep -q '^m[[:space:]]*tumble[[:space:]]*dialout' "$destdir/usr/lib/sysusers.d/tumble.conf" ||
          fail "no sysusers file putting tumble in dialout installed" ;;
      "sysctl --system"*) grep -q '^net.core.rmem_max *= *8388608' "$destdir/usr/lib/sysctl.d/60-tumble.conf" ||
          fail "no sysctl drop-in raising net.core.rmem_max installed" ;;
      journalctl*) ;;
      *) host=0 ;;
    esac
  done <<<"${c//&&/$'\n'}"
  [ $host -eq 1 ] && echo "not run ($why): $1"
  [ $host -eq 1 ]
}

config=$destdir/etc/tumble/tumbled.yaml
recording_sim=
# sim_late_ms N: how late run N of the simulator was at worst (its summary).
sim_late_ms() { sed -n 's/.*(worst \([0-9.]*\) ms).*/\1/p' "$work/sim-$1.err"; }
# A recording made while the simulator ran over 100 ms late has gaps in the
# sensors' arrival times that a real rig's would not (at 0.8 and 1.1 s late
# the calibration's first pass did not settle; at 42 ms it calibrated within
# 0.02 deg): what the calibration and the replay make of it says nothing
# about tumble.
too_late_to_judge() { awk -v ms="$(sim_late_ms "$recording_sim")" 'BEGIN { exit !(ms > 100) }'; }
skip_too_late() {
  echo "SKIP: the simulator ran $(sim_late_ms "$recording_sim") ms late while it was recorded (a loaded" \
    "machine): the recording does not hold the rig's motion"
  exit 77
}
calibration=$work/calibration.yaml
pasted=0
service_started=0

# eth0_rx_packets: the packets this namespace's eth0 has received. From
# /proc/net/dev, which is the reading process's network namespace; not from
# /sys/class/net, which is the namespace of whoever mounted /sys (without a
# mount namespace of its own, the host's: its eth0, if it has one).
eth0_rx_packets() { sed -n 's/^ *eth0: *//p' /proc/net/dev | awk '{ print $2 }'; }
# udp_datagrams_received: UDP datagrams this namespace has received, to a
# socket or to a port nothing listens on (/proc/net/snmp, also per
# namespace). At step 1 only the lidar sends UDP here: lo carries no LCM yet.
udp_datagrams_received() {
  awk '$1 == "Udp:" { if (!n++) { for (i = 2; i <= NF; i++) col[$i] = i } else print $col["InDatagrams"] + $col["NoPorts"] }' /proc/net/snmp
}

# run_command COMMAND COMMENT: runs it here, in this shell (so `run=…`
# carries on), with what the document says it prints checked where a test can.
run_command() {
  local doc=$1 comment=$2 c out status
  echo "\$ $doc"
  host_only "$doc" && return 0
  c=$(as_here "$doc")
  case $doc in
    *tcpdump*)
      if [ "$TUMBLE_IN_PRIVATE_NETWORK" = user ]; then
        # What `tcpdump -c 3` under `timeout 10` waits for: three UDP
        # datagrams, within 10 s (until the address was added, nothing
        # answered the lidar's ARP requests: its first datagrams wait).
        local udp_before eth0_before udp_now eth0_now tenths=0
        udp_before=$(udp_datagrams_received)
        eth0_before=$(eth0_rx_packets)
        [ -n "$udp_before" ] && [ -n "$eth0_before" ] || fail "no Udp: in /proc/net/snmp or no eth0 in /proc/net/dev"
        while udp_now=$(udp_datagrams_received) && eth0_now=$(eth0_rx_packets) &&
              { [ "$udp_now" -lt $((udp_before + 3)) ] || [ "$eth0_now" -lt $((eth0_before + 3)) ]; }; do
          [ $tenths -ge 100 ] && fail "fewer than 3 UDP datagrams on eth0 in 10 s"
          sleep 0.1
          tenths=$((tenths + 1))
        done
        echo "not run (tcpdump cannot change to its user in a user namespace): within $((tenths / 10)).$((tenths % 10)) s" \
          "eth0 received $((eth0_now - eth0_before)) packets, this namespace $((udp_now - udp_before)) UDP datagrams"
        return 0
      fi
      out=$(eval "timeout 10 $c" 2>/dev/null) || fail "tcpdump saw no 3 packets: $out"
      echo "$out"
      # The simulator sends from a port of its own; the RS-16 from 6699.
      local expected
      expected=$(printf '%s' "$comment" | sed 's/\./\\./g; s/\\\.[0-9]* >/\\.[0-9]* >/')
      [ "$(grep -c -- "$expected\$" <<<"$out")" -eq 3 ] || fail "tcpdump printed other lines than \"$comment\""
      ;;
    sysctl\ net.core.rmem_max*)
      out=$(eval "$c") || fail "$doc failed"
      echo "$out"
      grep -qx 'net.core.rmem_max = [0-9]*' <<<"$out" || fail "not a line like \"$comment\""
      ;;
    tumbled*--record*)
      stop_sim
      start_sim 10 --mti-start config --start-when-measuring
      recording_sim=$qs_sims
      eval "exec $c" >"$work/record.log" 2>&1 &
      local tumbled=$!
      qs_background+=("$tumbled")
      wait "$qs_sim"
      qs_sim=
      sleep 0.5
      kill -INT "$tumbled"
      wait "$tumbled"
      status=$?
      tail -3 "$work/record.log"
      [ $status -eq 0 ] || fail "tumbled --record exited $status: $(cat "$work/record.log")"
      ;;
    tumble-calib\ rig*)
      eval "$c" >"$work/calib.out" 2>&1
      status=$?
      cat "$work/calib.out"
      [ $status -ne 0 ] && too_late_to_judge && skip_too_late
      [ $status -eq 0 ] || fail "tumble-calib rig exited $status"
      sed -n '/^# for tumbled.yaml/,$p' "$work/calib.out" | sed -n '/^imu:$/,$p' | sed '1d' >"$calibration"
      [ -s "$calibration" ] || fail "tumble-calib rig printed no lines for tumbled.yaml"
      ;;
    tumble-eval\ imu*)
      eval "$c" || fail "exit $?"
      [ -s check/report.md ] && [ -s check/roll_pitch.png ] || fail "no check/report.md and check/roll_pitch.png"
      ;;
    *"echo configuration OK"*)
      out=$(eval "$c") || fail "exit $?: $out"
      echo "$out"
      [ "$out" = "configuration OK" ] || fail "printed \"$out\""
      ;;
    tail\ -1\ run.tum*)
      out=$(eval "$c") || fail "$doc failed"
      echo "$out"
      [ "$(wc -w <<<"$out")" -eq 8 ] || fail "not one pose of 8 numbers (\"$comment\")"
      ;;
    *)
      eval "$c"
      status=$?
      [ $status -eq 0 ] || fail "exit $status"
      ;;
  esac
}

# paste_calibration: step 6 as documented, with what tumble-calib printed.
paste_calibration() {
  [ $pasted -eq 1 ] && return 0
  pasted=1
  [ -s "$calibration" ] || fail "nothing to paste: tumble-calib rig did not run before step 6"
  # The document's example has the keys tumble-calib prints, in its order.
  local keys_doc keys_printed
  keys_doc=$(grep -o '^ *[a-zA-Z_]*:' "$work/paste_example.yaml" | tr -d ' ')
  keys_printed=$(grep -o '^ *[a-zA-Z_]*:' "$calibration" | tr -d ' ')
  [ "$keys_doc" = "$keys_printed" ] || fail "the documented example's keys ($keys_doc) are not tumble-calib's ($keys_printed)"
  # "A translation printed NOT OBSERVABLE is measured on the mount": here the
  # simulated mount's, from the scenario.
  if grep -q 'translation_m:.*NOT OBSERVABLE' "$calibration"; then
    local measured
    measured=$(sed -n 's/.*T_LI: {translation_m: \(\[[^]]*\]\).*/\1/p' \
      "$source_dir/tools/sim/scenarios/handheld_waving.yaml")
    [ -n "$measured" ] || fail "the scenario gives no T_LI translation_m"
    sed -i "s/^\( *translation_m: \).*NOT OBSERVABLE.*/\1$measured  # measured on the mount/" "$calibration"
  fi
  awk -v section=imu -v paste="$calibration" -f "$here/config_edit.awk" "$config" >"$work/edited.yaml" ||
    fail "cannot paste under imu: in $config"
  cp "$work/edited.yaml" "$config"
  echo "pasted under imu: in /etc/tumble/tumbled.yaml:"
  cat "$calibration"
}

apply_setting() {
  local setting
  setting=$(as_here "$1")
  echo "set in /etc/tumble/tumbled.yaml: $1"
  awk -v set="$setting" -f "$here/config_edit.awk" "$config" >"$work/edited.yaml" ||
    fail "$1: no such key in the installed configuration"
  cp "$work/edited.yaml" "$config"
}

# start_service: what `systemctl enable --now tumbled` starts, the installed
# unit's ExecStart=, on sensors that keep sending.
start_service() {
  [ $service_started -eq 1 ] && return 0
  service_started=1
  local exec
  exec=$(sed -n 's/^ExecStart=//p' "$destdir/usr/lib/systemd/system/tumbled.service")
  [ -n "$exec" ] || fail "the installed unit has no ExecStart="
  echo "started as the unit's ExecStart=: $exec"
  exec=${exec//\/etc\/tumble\//$destdir/etc/tumble/}
  exec=${exec/\/usr\/bin\/tumbled/$destdir/usr/bin/tumbled}
  start_sim 12 --mti-start config --start-when-measuring
  $exec >"$work/service.log" 2>&1 &
  qs_background+=("$!")
}

# watch_command COMMAND: started beside the service, stopped after it.
watch_command() {
  local c
  echo "\$ $1"
  c=$(as_here "$1")
  eval "exec $c" >"$work/watch-${#qs_background[@]}.log" 2>&1 &
  qs_background+=("$!")
}

# After every step has run: what the service and the watchers saw.
check_service_and_watchers() {
  sleep 1
  curl -sf -o "$work/page.html" http://127.0.0.1:8076/ || fail "tumble-view serves no page on :8076"
  curl -sf -o /dev/null http://127.0.0.1:8076/three/three.min.js || fail "tumble-view serves no three.js"
  echo "tumble-view: page served ($(wc -c <"$work/page.html") bytes)"
  wait "$qs_sim"
  qs_sim=
  sleep 1
  for pid in "${qs_background[@]}"; do kill -INT "$pid" 2>/dev/null; done
  sleep 1
  grep -q 'state initialising -> tracking' "$work/service.log" ||
    fail "the service never tracked: $(tail -20 "$work/service.log")"
  grep 'final status' "$work/service.log"
  [ -s "$HOME/tumble.lcmlog" ] || fail "lcm-logger wrote no tumble.lcmlog"
  local channel count
  for channel in TUMBLE_ODOM TUMBLE_POSE TUMBLE_STATUS; do
    count=$(grep -a -o "$channel" "$HOME/tumble.lcmlog" | wc -l)
    echo "tumble.lcmlog: $count $channel messages"
    [ "$count" -gt 0 ] || fail "lcm-logger logged no $channel"
  done
}

# The steps, in the documents' order: the README's first, then what
# docs/robot-setup.md adds to the same step.
steps=$work/steps.tsv
{
  awk -v from='^## Install on a robot' -v to='^## ' -v step='^\\*\\*[0-9]+\\. ' \
    -f "$here/doc_steps.awk" "$source_dir/README.md"
  awk -v from='^## Quick start' -v to='^## ' -v step='^\\*\\*[0-9]+\\. ' \
    -f "$here/doc_steps.awk" "$source_dir/README.md"
  awk -v from='^## 1\\. ' -v to='^## Reporting' -v step='^## [0-9]+\\. ' \
    -f "$here/doc_steps.awk" "$source_dir/docs/robot-setup.md"
} | sort -s -t "$(printf '\t')" -k1,1n | awk -F '\t' '!seen[$2 FS $3]++' >"$steps"
grep -q "$(printf '\tcmd\t')" "$steps" || fail "no commands found in the documents"
awk -F '\t' '$2 == "paste" { print $3 }' "$steps" >"$work/paste_example.yaml"

current=-1
while IFS=$'\t' read -r step kind text comment <&3; do
  if [ "$step" != "$current" ]; then
    current=$step
    say "step $step"
    [ "$step" -eq 1 ] && start_sim 30
    [ "$step" -eq 3 ] && stop_sim
  fi
  case $kind in
    cmd) run_command "$text" "$comment" ;;
    set) apply_setting "$text" ;;
    paste) paste_calibration ;;
    watch) start_service; watch_command "$text" ;;
  esac
done 3<"$steps"
[ $service_started -eq 1 ] || fail "no watch step found"
say "the service and what watched it"
check_service_and_watchers

# Step 7's check, beyond its exit status: the replay tracked the whole
# recording and ended near where the rig started (it waved about one place,
# within 0.15 m; replays ended 0.10 m off). The bar is 2 m: replayed without
# the calibration the rig was lost after 42 scans, 18.7 m off; with it, a
# recording made while a loaded machine ran its tumbled late ended 1.1 m off.
# A recording made while the simulator ran over 100 ms late is not judged: at
# 416 ms late (as a user, at normal priority, beside a build) the replay lost
# the rig after 50 scans; the test is then skipped, as at step 5.
say "the replay's trajectory"
awk -v late_ms="$(sim_late_ms "$recording_sim")" '!/^#/ { if (!n++) { x = $2; y = $3; z = $4 } ex = $2; ey = $3; ez = $4 }
  END { d = sqrt((ex-x)^2 + (ey-y)^2 + (ez-z)^2)
        printf "%d poses, the last %.3f m from the first; the simulator ran up to %.1f ms late\n", n, d, late_ms
        if (late_ms > 100) print "too late to judge the distance: not judged"
        exit !(n >= 80 && (late_ms > 100 || d < 2)) }' "$HOME/run.tum" ||
  { too_late_to_judge && skip_too_late; fail "the replay did not track the recording"; }
echo "PASS"
