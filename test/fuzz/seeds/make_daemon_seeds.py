#!/usr/bin/env python3
"""Writes fuzz_daemon's seeds (its operation list: see fuzz_daemon.cpp), each
a run that reaches registered, tracking scans and then a fault on the wire:
daemon_clean.bin (rest, then turning and moving), daemon_second_sender.bin (a
second host sends a room seen from elsewhere), daemon_stall.bin (the motor
stalls, the lasers firing on), daemon_bad_imu.bin (an MTData2 frame of NaN and
out-of-range numbers) and daemon_garbage.bin (foreign and malformed
datagrams, serial garbage, arrival time running back). Run it from this folder
to regenerate."""
import struct

STALL, NO_IMU, NO_LIDAR, ECHO, ECHO_ELSEWHERE = 2, 4, 8, 1, 1 | 32


def move(periods, yaw_rate_steps=0, speed_steps=0, flags=0):
    """periods of 10 ms; yaw rate in 0.05 rad/s, speed in 0.02 m/s."""
    out = b""
    while periods > 0:
        n = min(periods, 256)
        out += struct.pack("<BBbbB", 0, n - 1, yaw_rate_steps, speed_steps, flags)
        periods -= n
    return out


def imu_values(accel, gyro):
    return bytes([4, 0]) + struct.pack("<6f", *accel, *gyro)


def serial(data):
    return bytes([4, len(data)]) + data


def raw_datagram(flags, payload):
    return bytes([5, flags]) + struct.pack(">H", len(payload)) + payload


def framed(flags, body):
    return bytes([6, flags]) + body


def time_jump(steps):
    return bytes([7]) + struct.pack("<b", steps)


REST = move(40)
SEEDS = {
    "daemon_clean.bin": REST + move(70, 10, 10),
    "daemon_second_sender.bin": REST + move(40, 10) + move(40, 10, 0, ECHO_ELSEWHERE),
    "daemon_stall.bin": REST + move(30, 4) + move(40, 4, 0, STALL) + move(30, 4),
    "daemon_bad_imu.bin": REST + move(30, 4) + imu_values((float("nan"), 0, 9.81), (0, 0, float("inf")))
    + imu_values((1e6, 0, 9.81), (1e3, 0, 0)) + move(30, 4),
    "daemon_garbage.bin": REST + move(30) + raw_datagram(1, bytes(range(256)) * 4) + framed(0, bytes(range(200)))
    + serial(bytes([0xFA, 0xFF, 0x36, 0x05, 1, 2, 3])) + time_jump(-2) + move(20, 0, 0, NO_LIDAR) + move(30),
}

for name, data in SEEDS.items():
    with open(name, "wb") as f:
        f.write(data)
