#!/usr/bin/env python3
"""Writes the seed inputs of the fuzz targets into fuzz/seeds/<target>/.

Deterministic: the same repository gives the same files. `scripts/fuzz.sh`
runs each target on fuzz/corpus/<target>/ (the minimised corpus kept in the
repository) and these seeds; rerun this script when the formats change.

- run_csv: the head of every bundled run, a run with declared missing
  samples, a few near-misses.
- mechanism_toml: the bundled mechanisms, and one with a curve spring and
  friction with every key.
- frame_decode: telemetry frames of Sample<N> and Status<N> (postcard, then
  CRC-32C little endian, COBS, 0x00), as core/src/telemetry.rs writes them;
  a stream of several frames with noise between.
- monitor_update: the bundled seed001 T01 runs as the target's 8-byte
  records (see fuzz_targets/monitor_update.rs), and a record stream with
  every bad time stamp and a missing reading.
"""

import math
import os
import struct
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "fuzz", "seeds")


def write(target, name, data):
    d = os.path.join(OUT, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def data_files(sub, ext):
    base = os.path.join(ROOT, "data", sub)
    out = []
    for dirpath, _, files in os.walk(base):
        out += [os.path.join(dirpath, f) for f in files if f.endswith(ext)]
    return sorted(out)


# --- run_csv ---------------------------------------------------------------

def run_csv():
    for path in data_files("examples", ".csv") + data_files("reference", ".csv"):
        lines = open(path).read().splitlines()[:25]
        name = os.path.relpath(path, os.path.join(ROOT, "data")).replace("/", "_")
        write("run_csv", name, "\n".join(lines) + "\n")
    missing = (
        '# mechanism = "seed001-T01"\n'
        '# faults = "dropout:joint=2:start=0.01:duration=0.02:mode=missing"\n'
        '# missing_samples = "NaN"\n'
        "t_s,phi1_deg,phi2_deg,phi3_deg,latch1,latch2,latch3\n"
        "0.000,-90.000000,179.978027,-180.000000,0,0,0\n"
        "0.010,-89.978027,NaN,-179.978027,0,0,0\n"
        "0.020,-89.956055,NaN,-179.956055,0,0,0\n"
        "0.030,-89.890137,179.890137,-179.912109,0,0,1\n"
    )
    write("run_csv", "missing_samples.csv", missing)
    write("run_csv", "crlf_bom.csv", "\ufeff" + missing.replace("\n", "\r\n"))
    write("run_csv", "undeclared_nan.csv", missing.replace('# missing_samples = "NaN"\n', ""))
    write("run_csv", "range.csv", "t_s,phi1_deg,latch1\n0,-90,0\n0.01,720.5,1\n")
    write("run_csv", "one_joint.csv", "t_s,phi1_deg,latch1\n0,-90,0\n0.000001,-89.9,0\n1e-6,0,1\n")


# --- mechanism_toml --------------------------------------------------------

CURVE = """name = "curve-and-friction"
description = "one panel, a curve spring, friction with every key"

[[panel]]
length_m = 0.5
mass_kg = 2.0
com_m = 0.25
inertia_kgm2 = 0.05

[[joint]]
stowed_deg = -90.0
spring = { kind = "curve", unfold = [[0.0, 0.0], [1.2, 30.0], [90.0, 1.5]], fold = [[0.0, 0.0], [1.0, 20.0], [90.0, 1.0]], interp = "linear", count = 2 }
friction = { coulomb_nm = 0.1, viscous_nms = 0.01, coulomb_threshold_rad_s = 0.02, breakaway_nm = 0.2, stribeck_rad_s = 0.05 }

[run]
duration_s = 3.0
sample_hz = 200.0
"""


def mechanism_toml():
    for path in data_files("mechanisms", ".toml"):
        write("mechanism_toml", os.path.basename(path), open(path).read())
    write("mechanism_toml", "curve_friction.toml", CURVE)


# --- frame_decode ----------------------------------------------------------

def crc32c(data):
    poly = 0x82F63B78
    crc = 0xFFFFFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ (poly if crc & 1 else 0)
    return crc ^ 0xFFFFFFFF


def cobs(data):
    out = bytearray()
    block = bytearray()
    for b in data:
        if b == 0:
            out.append(len(block) + 1)
            out += block
            block = bytearray()
        else:
            block.append(b)
            if len(block) == 254:
                out.append(255)
                out += block
                block = bytearray()
    out.append(len(block) + 1)
    out += block
    return bytes(out)


def frame(payload):
    return cobs(payload + struct.pack("<I", crc32c(payload))) + b"\x00"


def varint(n):
    out = bytearray()
    while True:
        b = n & 0x7F
        n >>= 7
        if n:
            out.append(b | 0x80)
        else:
            out.append(b)
            return bytes(out)


def f32(x):
    return struct.pack("<f", x)


def sample(t, phis, latches):
    return f32(t) + b"".join(f32(p) for p in phis) + bytes(1 if l else 0 for l in latches)


def opt(x):
    return b"\x00" if x is None else b"\x01" + f32(x)


def joint_status(phi, rate, latch, prediction, faults, margin=None, ttl=None):
    # phi, rate, coulomb, coulomb_sd, viscous, viscous_sd, friction torque,
    # latch state, margin, prediction, confidence, time to latch, faults.
    return (
        f32(phi) + f32(rate) + f32(0.2) + f32(0.05) + f32(0.01) + f32(0.002) + f32(0.19)
        + varint(latch) + opt(margin) + varint(prediction) + f32(0.9) + opt(ttl) + varint(faults)
    )


def status(t, samples, joints):
    return f32(t) + varint(samples) + b"".join(joints)


def frame_decode():
    s3 = frame(sample(0.01, [-90.0, 180.0, -180.0], [False, False, False]))
    s3n = frame(sample(1.5, [float("nan"), 0.0, -3.0], [True, False, True]))
    s1 = frame(sample(0.5, [-45.0], [False]))
    st3 = frame(status(1.0, 100, [
        joint_status(-40.0, 80.0, 1, 1, 0, margin=120.0, ttl=0.8),
        joint_status(90.0, -60.0, 1, 0, 1 << 2),
        joint_status(0.0, 0.0, 3, 1, (1 << 9) | (1 << 8)),
    ]))
    st4 = frame(status(2.0, 70000, [joint_status(0.0, 0.0, 3, 1, 0)] * 4))
    write("frame_decode", "sample3", s3)
    write("frame_decode", "sample3_nan", s3n)
    write("frame_decode", "sample1", s1)
    write("frame_decode", "status3", st3)
    write("frame_decode", "status4", st4)
    write("frame_decode", "stream", b"\x13\x37" + s3 + st3 + b"\xff\xfe\x00" + s3n + st3[:-7])


# --- monitor_update --------------------------------------------------------

def records_of_run(path, step=1):
    rows = [l.split(",") for l in open(path).read().splitlines() if l and not l.startswith("#")][1:]
    n = (len(rows[0]) - 1) // 2
    assert n == 3, path
    # The target starts from the mechanism's stowed angles, seed001 T01's.
    prev_t, prev = 0.0, [-90.0, 180.0, -180.0]
    out = bytearray()
    for r in rows[::step]:
        t = float(r[0])
        phis = [float(x) for x in r[1:1 + n]]
        latches = [r[1 + n + j] == "1" for j in range(n)]
        dt_ms = max(1, min(256, round((t - prev_t) * 1000.0))) if out else 1
        ctrl = sum(1 << j for j in range(n) if latches[j])
        codes = []
        for j in range(n):
            c = max(-32768, min(32767, round((phis[j] - prev[j]) / 0.005)))
            prev[j] += c * 0.005
            codes.append(c)
        out += bytes([ctrl, dt_ms - 1]) + struct.pack("<3h", *codes)
        prev_t += dt_ms / 1000.0
    return bytes(out)


def monitor_update():
    for path in data_files("examples", ".csv"):
        if "seed001_T01" in path:
            name = os.path.relpath(path, os.path.join(ROOT, "data", "examples")).replace("/", "_")
            write("monitor_update", name + ".bin", records_of_run(path))
    smooth = records_of_run(os.path.join(ROOT, "data", "examples", "a_seed001_eft", "seed001_T01.csv"))
    bad = bytearray()
    for k in range(6):  # every bad time stamp of the target
        bad += bytes([0x40, k]) + struct.pack("<3h", 0, 0, 0)
    bad += bytes([0x08 | (1 << 4), 9]) + struct.pack("<3h", 10, 10, 10)  # joint 2 missing
    bad += bytes([0x80 | 0x07, 9]) + struct.pack("<3h", 0, 0, 0)  # absolute zero, switches closed
    write("monitor_update", "bad_times_then_deploy.bin", bytes(bad) + smooth[: 8 * 150])


def main():
    run_csv()
    mechanism_toml()
    frame_decode()
    monitor_update()
    for t in sorted(os.listdir(OUT)):
        files = os.listdir(os.path.join(OUT, t))
        size = sum(os.path.getsize(os.path.join(OUT, t, f)) for f in files)
        print(f"{t}: {len(files)} seeds, {size} bytes")


if __name__ == "__main__":
    sys.exit(main())
