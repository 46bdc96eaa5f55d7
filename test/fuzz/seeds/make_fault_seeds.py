#!/usr/bin/env python3
"""Writes the fuzz seeds for what networks do to the sensors' streams:
rs16_reordered.bin (fuzz_rs16's datagram-list input: MSOP packets with a
duplicate, swapped neighbours and one late after its scan closed, across a
scan split) and mti_reordered.bin (fuzz_mti's input: MTData2 frames with a
repeated and older PacketCounters). Run it from this folder to regenerate."""
import datetime
import struct

MSOP_MAGIC = bytes([0x55, 0xAA, 0x05, 0x0A, 0x5A, 0xA5, 0x50, 0xA0])
START = datetime.datetime(2024, 1, 1, tzinfo=datetime.timezone.utc)
PACKET_S = 12 * 111e-6
BLOCK_STEP = 39.96  # 0.01 deg per block at 600 rpm


def utc_field(t):
    us = round(t.microsecond)
    return bytes([t.year - 2000, t.month, t.day, t.hour, t.minute, t.second]) + struct.pack(">HH", us // 1000, us % 1000)


def msop(index, start_azimuth=35000.0):
    p = bytearray(1248)
    p[0:8] = MSOP_MAGIC
    p[20:30] = utc_field(START + datetime.timedelta(seconds=index * PACKET_S))
    p[30] = 0x01
    for b in range(12):
        at = 42 + 100 * b
        azimuth = int(round(start_azimuth + BLOCK_STEP * (index * 12 + b))) % 36000
        p[at:at + 4] = bytes([0xFF, 0xEE]) + struct.pack(">H", azimuth)
        for c in range(32):
            p[at + 4 + 3 * c:at + 7 + 3 * c] = struct.pack(">HB", 2000 + 10 * c, c)
    p[1246:1248] = bytes([0x00, 0xFF])
    return bytes(p)


def rs16_seed():
    order = [0, 1, 2, 2, 4, 3, 5, 6, 7, 9, 8, 10, 11, 8, 12, 13, 12, 14]  # 0 deg is crossed in packet ~8
    out = bytearray([0x10])  # free clock, split at 0 deg
    for i in order:
        out += bytes([0x00]) + struct.pack(">H", 1248) + msop(i)
    return bytes(out)


def xbus(mid, payload):
    body = bytes([0xFF, mid, len(payload)]) + payload
    return bytes([0xFA]) + body + bytes([(-sum(body)) & 0xFF])


def mtdata2(counter, sample_time_fine):
    p = struct.pack(">HBH", 0x1020, 2, counter) + struct.pack(">HBI", 0x1060, 4, sample_time_fine)
    p += struct.pack(">HB3f", 0x4020, 12, 0.1, -0.2, 9.8) + struct.pack(">HB3f", 0x8020, 12, 0.01, 0.02, -0.03)
    return xbus(0x36, p)


def mti_seed():
    out = bytearray([54])  # one frame per serial read
    for c in [1, 2, 2, 4, 3, 5, 6, 4, 7, 65535, 0, 8]:
        out += mtdata2(c, 100 * c)
    return bytes(out)


if __name__ == "__main__":
    with open("rs16_reordered.bin", "wb") as f:
        f.write(rs16_seed())
    with open("mti_reordered.bin", "wb") as f:
        f.write(mti_seed())
