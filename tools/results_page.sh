#!/usr/bin/env bash
# Writes DOCS_DIR/results.md and its plots (DOCS_DIR/results/) from the
# folders tools/results.sh made in OUT_DIR. Every figure on the page comes
# from OUT_DIR; the prose here says what each table is and never quotes one.
#
#   tools/results_page.sh OUT_DIR DOCS_DIR
set -euo pipefail
[[ $# -eq 2 ]] || { echo "usage: $0 OUT_DIR DOCS_DIR" >&2; exit 2; }
out=$1 docs=$2
needed=(bench1-cage bench2-cage bench1-gvtw bench2-gvtw bench2-long speed faults demo calib benchmarks live soak)
[[ -f $out/commit ]] || { echo "$out/commit is missing: run tools/results.sh first" >&2; exit 1; }
for step in "${needed[@]}"; do
  [[ -f $out/$step/.done ]] || { echo "$out/$step is not finished: run tools/results.sh first" >&2; exit 1; }
done

# The body of a tumble-eval report's section "## TITLE…", its own headings
# made level 4 so they sit under the page's.
section() {
  awk -v title="## $2" 'index($0, title) == 1 { on = 1; next } /^## / { on = 0 } on' "$1" |
    sed 's/^## /#### /; /^!\[/d'
}

# One row per run of a matrix's runs.csv whose kind is KIND: the columns
# named, as a markdown table under their given headings.
runs_table() {  # runs_table RUNS_CSV KIND "column=heading" ...
  local csv=$1 kind=$2
  shift 2
  awk -F, -v kind="$kind" -v specs="$*" '
    NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i
              n = split(specs, spec, " ")
              for (j = 1; j <= n; j++) { split(spec[j], kv, "="); name[j] = kv[1]; head[j] = kv[2]
                                         if (!(name[j] in col)) { print "no column " name[j] > "/dev/stderr"; exit 1 } }
              line = "|"; rule = "|"
              for (j = 1; j <= n; j++) { h = head[j]; gsub(/_/, " ", h); line = line " " h " |"; rule = rule "---|" }
              print line; print rule; next }
    $col["kind"] == kind { line = "|"; for (j = 1; j <= n; j++) line = line " " $col[name[j]] " |"; print line }' "$csv"
}

fenced() { echo '```'; cat "$@"; echo '```'; }

mkdir -p "$docs/results"
cp "$out/bench1-cage/boxplot.png" "$docs/results/cage-matrix.png"
cp "$out/bench2-cage/boxplot.png" "$docs/results/bench2-cage-matrix.png"
cp "$out/calib/calib_linear.png" "$out/calib/calib_angular.png" "$docs/results/"
cp "$out/demo/plots/trajectory_top.png" "$docs/results/default-run-top.png"
cp "$out/demo/plots/error.png" "$docs/results/default-run-error.png"

made_from=$(cat "$out/commit")
cpu=$(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)

{
cat <<EOF
# Results

For whoever wants to know how well tumbled does, and to check it. Every
figure is on simulated data: no public RS-16 + MTi-30 capture of extreme
motion exists, so \`tumble-sim\` (the paper's bench in software:
\`tools/sim/README.md\`) generates the runs with ground truth. Why each
default is what it is, with the figures that chose it, is in
[decisions/](decisions/README.md). Bench figures move by up to ±15 % from
nothing ([decisions/bench-noise.md](decisions/bench-noise.md)).

This page is written by \`tools/results.sh\`; do not edit it by hand. This
version: tumble $made_from, on $(date -u +%F), $(nproc) cores ($cpu), a
machine others were using too.

## Making them again

\`\`\`sh
./tumble build
tools/results.sh build/release DATA_DIR OUT_DIR
\`\`\`

It makes the two benches into \`DATA_DIR\` if they are not there, runs every
evaluation below into its own folder of \`OUT_DIR\` and writes this page and
its plots (about two hours on 2 cores; an interrupted run goes on where it
stopped). The benches:

- **bench1**: \`tumble-sim bench --seed 1 --out DATA_DIR/bench1\`: rail runs
  at 0.25–3.5 m/s, turntable runs at 0.5–11 rad/s and 46 rolling-cage runs in
  the garage scene (rolls of 3–11 rad/s, bounces to 200 m/s², jolts to
  800 rad/s²).
- **bench2**: the same with \`--realistic\`: every sensor error source on at
  its datasheet magnitude, the rig's lidar–IMU time offset (unknown to
  tumbled), the cage's bars, long out-and-back runs (garage, corridor, yard)
  and runs with people (three cage runs, each with no people, four
  walkers, the rope puller, and both).

Each evaluation is one \`tumble-eval\` command (\`tools/eval/README.md\`).
Error = final pose error over distance travelled (cm/m, deg/m), as in the
paper; RPE over 1 m unless said.

## The paper's matrix: 46 rolling-cage runs (§V-B)

\`tumble-eval matrix BENCH --kinds cage\`: every weight model with and without
de-skew. Medians and quartiles over the runs that did not diverge: over
100 cm/m or 45 deg/m, or no pose in the run's last second. Without de-skew
tumbled loses track on many cage runs; it says so (\`lost\`) and waits for the
robot to rest before it starts a new map, so those runs end without poses
and count as diverged.
EOF
for bench in bench1 bench2; do
  echo
  echo "### $bench"
  echo
  section "$out/$bench-cage/results.md" "Final pose error"
  section "$out/$bench-cage/results.md" "Against the paper"
done
cat <<'EOF'

![bench1: final pose error per model, left without de-skew, right with](results/cage-matrix.png)
![bench2: final pose error per model, left without de-skew, right with](results/bench2-cage-matrix.png)

The paper's real-data figures are larger than the simulated ones: the
simulated sensors at their datasheet magnitudes leave far less de-skew error
than the paper's rig, and no single error source explains the difference
([decisions/deskew-and-weights.md](decisions/deskew-and-weights.md)).

## Every run, tumbled's default (GVTW + de-skew)

`tumble-eval matrix BENCH --models GVTW --deskew on --kinds rail turntable cage people`:
every run but the long ones, which end where they started and are below.
EOF
for bench in bench1 bench2; do
  echo
  echo "### $bench"
  echo
  echo "Final pose error:"
  section "$out/$bench-gvtw/results.md" "Final pose error"
  echo "Relative pose error over 1 m:"
  section "$out/$bench-gvtw/results.md" "Relative pose error"
done
cat <<'EOF'

### People (bench2)

Each cage run with no people, four walkers, the rope puller, and both; the
runaway is the largest rise of the position error while published as good.

EOF
runs_table "$out/bench2-gvtw/runs.csv" people run=run translation_cm_per_m=cm/m \
  rpe_translation_cm_per_m=RPE_cm/m runaway_growth_m=runaway_m status=status
cat <<'EOF'

### Long runs (bench2)

`tumble-eval matrix BENCH2 --models GVTW --deskew on --kinds long --segment-m 10`:
the rolling cage and a walk, out and back in the garage, the corridor (400 m
of tube, nothing along its axis within the lidar's range) and the yard; RPE
over 10 m, in cm/m (= %). In the corridor tumbled reports the pose degraded,
then lost; its final error there is the IMU's dead reckoning.

EOF
runs_table "$out/bench2-long/runs.csv" long run=run distance_m=distance_m translation_cm_per_m=final_cm/m \
  rpe_translation_cm_per_m=RPE_10_m_cm/m runaway_growth_m=runaway_m status=status
cat <<'EOF'

## Knowing when the pose is wrong

`tumble-eval integrity BENCH EVAL` on the matrices above: tumbled's verdict
(what puts it in degraded) and its expected error as detectors of wrong
poses, the NEES of its published covariance, and the runaway while published
as good.
EOF
for eval_dir in "bench1-gvtw|bench1" "bench2-gvtw|bench2" "bench2-long|bench2, the long runs"; do
  echo
  echo "### ${eval_dir#*|}"
  echo
  sed 's/^## /#### /' "$out/${eval_dir%%|*}/integrity.md"
done
cat <<'EOF'

## The default run (`./tumble demo --rate max`)

A rolling cage pulled at 10 rad/s with bounces and jolts
(`tools/sim/scenarios/default.yaml`), replayed through tumbled at full speed
and scored against its ground truth:

EOF
grep -v "^Plots: " "$out/demo/demo.md"
cat <<'EOF'

![the default run from above: tumbled against ground truth](results/default-run-top.png)
![the default run: position error over time](results/default-run-error.png)

## Speed

Figures from a shared machine; medians.

### The pipeline per scan

`tumble-eval speed BENCH1 --kinds cage --runs 'cage-0[1-6]'`:

EOF
sed '/^# /d; /^Bench `/d; s/^## /#### /' "$out/speed/speed.md"
cat <<'EOF'

### Microbenchmarks

`bench_core_registration --benchmark_filter=GVTW` (a whole RS-16 scan,
registered), `bench_rs16` (decode and scan assembly) and `bench_mti` (frames
to timed samples), each `--benchmark_repetitions=3`, medians:

EOF
cat "$out/benchmarks/"{registration,rs16,mti}.txt | awk '/_median/ { printf "%-80s %s %s\n", $1, $2, $3 }' | fenced
cat <<'EOF'

### Live

`tools/live_latency.sh build/release`: `tumble-sim live` streams the default
run in real time (lidar to 127.0.0.1, the IMU's bytes into a pty) and tumbled
runs live against it. IMU bytes read → `TUMBLE_ODOM` handed to LCM, and scan
complete → `TUMBLE_POSE`; without real-time priority (the installed unit runs
tumbled with `daemon.realtime_priority=20`, which this user may not have):

EOF
grep -E 'latency over the run|peak RSS' "$out/live/latency.txt" | sed 's/^\[info\] //' | fenced
cat <<'EOF'

`tools/soak.sh build/release`: ten minutes live, tumbled's resident memory
sampled every 10 s:

EOF
fenced "$out/soak/soak.txt"
cat <<'EOF'

## Sensor faults

`tools/fault_table.sh build/release OUT BENCH2/cage-0{1,2,3}`: each fault
alone, rewritten by `tumble-sim faults` and replayed at `--rate max`. The
bar: 1.5× the clean run + 0.5 cm/m for packet faults, 5 cm/m for gaps, or
reported lost and re-initialised; a runaway while good under 0.5 m.

EOF
cat "$out/faults/faults.md"
cat <<'EOF'

Faults of the host rather than the sensors, each shown by its test (they
cannot be replayed from a recording):

| fault | result |
|---|---|
| the lidar port busy, or its address not yet assigned | retried with backoff (0.25 s doubling to 8 s), a warning each time; `waiting_for_sensors` meanwhile (`TumbledProcess.ABusyLidarPortIsRetriedUntilItIsFree`, `…AnAddressNotYetAssignedIsRetriedUntilShutdown`) |
| tumbled exits 1 again and again | systemd restarts it every 5 s, without a start limit; exit 2 (bad configuration) is not restarted (`SystemdUnit.RestartsForeverWithoutAStartLimit`) |
| the trajectory file cannot be written | `status_t.trajectory_lines_lost`, a warning, exit 1 at the end; synced every `daemon.checkpoint_period_s`, so a power cut loses at most that (`TrajectoryFileTest.*`) |
| the recording disk below `record.min_free_mib` | the segment synced and closed, `status_t.record_paused`, drops counted in `record_dropped`, retried every 10 s; odometry goes on (`PcapRecorder.*`) |
| a recording create, write or sync fails | `status_t.record_errors`, paused 10 s, then a new segment; odometry goes on |
| the recorder's writer falls behind | the io thread never waits: drops counted in `record_dropped` |
| a fused speed beyond `fuser.max_speed_m_s` (a runaway) | lost ("fused speed beyond …"), the fuser restarts at the next rest (`CoreRegistrationStage.AFusedSpeedNoRobotReachesLosesTrackAndWaitsForTheNextRest`) |
| after an IMU gap, the IMU still while the registrations move the robot (a runaway in a scene that repeats) | lost ("moving beyond fuser.max_speed_at_rest_m_s …"), the fuser starts again at that rest (`ImuFuser.AfterAnImuGapARestThatFindsTheRobotMovingIsARunaway`, `CoreRegistrationStage.AFuserFoundMovingAtRestLosesTrackAndWaitsForTheNextRest`; [decisions/rest-check.md](decisions/rest-check.md)) |

Random input through the whole daemon, and what it found:
[security.md](security.md#random-input-through-the-whole-daemon).

## Calibration

`tumble-calib BENCH1` fits the paper's speed-uncertainty models; they do not
fit tumbled's de-skew error, so the defaults stay the paper's
([decisions/speed-uncertainty.md](decisions/speed-uncertainty.md)):

EOF
{ sed -n 's/^ *check: /check: /p' "$out/calib/calib.out"; sed -n '/^registration:/,$p' "$out/calib/calib.yaml"; } | fenced
cat <<'EOF'

![rail: residual vs speed, and the fitted log-normal against the true de-skew error](results/calib_linear.png)
![turntable: residual vs angular speed, and the cubic against the true de-skew error](results/calib_angular.png)

`tumble-calib rig` on simulated rigs (upside-down and tilted mounts) is
checked by its tests (`tools/calib/README.md`).
EOF
} | cat -s >"$docs/results.md.partial"
mv "$docs/results.md.partial" "$docs/results.md"
