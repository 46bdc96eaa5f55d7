# Sourced by tools/demo.sh and tools/arm64_same_answer.sh: the default
# simulated run, made once, and the IMU mounting it was made with.

# ensure_default_run SIM SCENARIO RUN_DIR LOG_FN: generates the run unless one
# newer than the scenario and the simulator is there (it depends on both).
ensure_default_run() {
  local sim=$1 scenario=$2 run=$3 log=$4
  if [ ! -f "$run/manifest.yaml" ] || [ "$scenario" -nt "$run/manifest.yaml" ] || [ "$sim" -nt "$run/manifest.yaml" ]; then
    "$log" "generating the default run ($scenario) into $run"
    rm -rf "$run"
    "$sim" run "$scenario" --out "$run" >&2
  else
    "$log" "reusing $run (delete it to regenerate)"
  fi
}

# mounting_of RUN_DIR: sets the array `mounting` to tumbled's --set options for
# the simulated IMU's mounting, from the run's manifest, as a robot's
# calibrated tumbled.yaml would give it.
mounting_of() {
  local manifest=$1/manifest.yaml
  extrinsic() { sed -n "/^  T_LI:/,/meaning:/s/^    $1: //p" "$manifest"; }
  mounting=(--set "imu.extrinsic_T_LI.translation_m=$(extrinsic translation_m)"
            --set "imu.extrinsic_T_LI.rotation_rpy_deg=$(extrinsic rpy_deg)")
}
