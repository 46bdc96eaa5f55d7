#!/usr/bin/env python3
"""What the IMU alone can do along a direction no scan observes (a corridor's axis).

An oracle for a tumble-sim run: attitude and the two other position axes are
taken from the ground truth, as if the lidar pinned them perfectly, and the
position along one world axis is dead-reckoned from the run's own IMU bytes
(read by tumble-dump, timed by the manifest's clock model). No estimator that
takes that axis from these two sensors does better than the first variant:

  tilt         W levelled from the mean accelerometer over the first second
               (the run's static start), as every estimator must: at rest a
               horizontal accelerometer bias and a tilt read the same.
  level-floor  the bias at rest known instead (as if the floor were known to be
               level): what is left is the bias's drift, scale, misalignment
               and noise.

Writes OUT-tilt.tum and OUT-level-floor.tum (the IMU's sample times) and prints
the final error along the axis; score them with
`tumble-eval score RUN/ground_truth.tum OUT-tilt.tum --segment-m 10`.
The run's IMU must sit at the lidar (T_LI identity: bench2's runs).
"""
import argparse
import csv
import io
import math
import subprocess


def manifest_value(lines, key):
    for line in lines:
        text = line.strip()
        if text.startswith(key + ':'):
            return text.split(':', 1)[1].strip()
    raise KeyError(f'{key} not in the manifest')


def rotate(q, v):
    x, y, z, w = q
    tx, ty, tz = 2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])
    return (v[0] + w * tx + y * tz - z * ty, v[1] + w * ty + z * tx - x * tz, v[2] + w * tz + x * ty - y * tx)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('run', help='tumble-sim run folder (manifest.yaml, imu.pcap, ground_truth.tum)')
    parser.add_argument('out', help='output prefix')
    parser.add_argument('--axis', type=int, default=0, choices=[0, 1],
                        help='horizontal world axis dead-reckoned (0 = x, the corridor)')
    parser.add_argument('--tumble-dump', default='build/release/tools/dump/tumble-dump')
    parser.add_argument('--static-s', type=float, default=1.0, help='levelling window at the start')
    args = parser.parse_args()

    manifest = open(f'{args.run}/manifest.yaml').read().splitlines()
    if manifest_value(manifest, 'quaternion_xyzw') != '[0, 0, 0, 1]' or \
            manifest_value(manifest, 'translation_m') != '[0, 0, 0]':
        raise SystemExit('the run\'s T_LI is not the identity')
    epoch_s = int(manifest_value(manifest, 'epoch_ns')) * 1e-9
    first_sample_s = float(manifest_value(manifest, 'first_sample_s'))
    first_time_fine = int(manifest_value(manifest, 'first_sample_time_fine'))
    drift_ppm = float(manifest_value(manifest, 'drift_ppm'))
    offset_s = float(manifest_value(manifest, 'imu_time_offset_s'))
    truth_rate_hz = float(manifest_value(manifest[manifest.index('ground_truth:'):], 'rate_hz'))
    rate_hz = float(manifest_value(manifest[manifest.index('imu:'):], 'rate_hz'))

    truth = [[float(f) for f in line.split()] for line in open(f'{args.run}/ground_truth.tum')
             if not line.startswith('#')]
    t0 = truth[0][0]

    def truth_at(t):
        # Linear between the poses: a rolling cage turns 2.7 mrad in a
        # millisecond, which leaks 0.026 m/s2 of gravity along the axis.
        u = (t - t0) * truth_rate_hz
        i = max(0, min(len(truth) - 2, int(math.floor(u))))
        w = min(1.0, max(0.0, u - i))
        a, b = truth[i], list(truth[i + 1])
        if sum(a[k] * b[k] for k in range(4, 8)) < 0:
            b[4:8] = [-c for c in b[4:8]]
        pose = [a[k] + w * (b[k] - a[k]) for k in range(8)]
        norm = math.sqrt(sum(c * c for c in pose[4:8]))
        return pose[:4] + [c / norm for c in pose[4:8]]

    dump = subprocess.run([args.tumble_dump, 'mti', f'{args.run}/imu.pcap'], capture_output=True, text=True,
                          check=True).stdout
    samples = []
    for row in csv.DictReader(io.StringIO(dump)):
        if not row['t_sensor_s'] or not row['ax']:
            continue  # a frame without a time or an acceleration
        # The manifest's clock: sample k is sent at first_sample_s + k / rate / (1 + drift) and is the
        # mean over the period centred imu_time_offset_s later.
        k = round((float(row['t_sensor_s']) * 1e4 - first_time_fine) / (1e4 / rate_hz))
        t = epoch_s + first_sample_s + k / rate_hz / (1 + drift_ppm * 1e-6) + offset_s
        samples.append((t, (float(row['ax']), float(row['ay']), float(row['az']))))

    at_rest = [rotate(truth_at(t)[4:8], f) for t, f in samples if t - t0 < args.static_s]
    mean = [sum(s[i] for s in at_rest) / len(at_rest) for i in range(3)]
    g = math.sqrt(sum(c * c for c in mean))
    # The levelled W: the small rotation taking the mean specific force to +z.
    tilt_x, tilt_y = mean[1] / g, -mean[0] / g

    def levelled(v):
        return (v[0] + tilt_y * v[2], v[1] - tilt_x * v[2], v[2] - tilt_y * v[0] + tilt_x * v[1])

    q_start = truth_at(samples[0][0])[4:8]
    standard_gravity = 9.80665  # tumble-sim's
    bias_body = rotate((-q_start[0], -q_start[1], -q_start[2], q_start[3]),
                       (mean[0], mean[1], mean[2] - standard_gravity))
    axis = args.axis
    for variant in ('tilt', 'level-floor'):
        position = truth_at(samples[0][0])[1 + axis]
        velocity = 0.0
        with open(f'{args.out}-{variant}.tum', 'w') as out:
            for k, (t, f) in enumerate(samples):
                dt = t - samples[k - 1][0] if k > 0 else 1.0 / rate_hz  # a sample is its period's mean
                pose = truth_at(t)
                specific_w = rotate(pose[4:8], f)
                if variant == 'tilt':
                    accel = levelled(specific_w)[axis]
                else:
                    accel = specific_w[axis] - rotate(pose[4:8], bias_body)[axis]
                position += velocity * dt + 0.5 * accel * dt * dt
                velocity += accel * dt
                xyz = pose[1:4]
                xyz[axis] = position
                out.write(f'{t:.9f} {xyz[0]:.6f} {xyz[1]:.6f} {xyz[2]:.6f} '
                          f'{pose[4]:.9f} {pose[5]:.9f} {pose[6]:.9f} {pose[7]:.9f}\n')
        print(f'{variant}: final error along axis {axis}: {position - truth_at(samples[-1][0])[1 + axis]:+.2f} m')


if __name__ == '__main__':
    main()
