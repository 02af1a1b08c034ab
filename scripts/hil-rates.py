#!/usr/bin/env python3
"""Hardware in the loop on QEMU at the rates a bench would try: each run of
`deploywatch hil` below on the serial-link firmware, one table row each
(statuses bit-identical with the host core, the firmware's counts, the
samples after which the prediction's slices yielded to a waiting frame,
latency, deadline misses), the host's load before each run.

    scripts/firmware.sh build
    scripts/measured.py run firmware-hil "Firmware: hardware in the loop on QEMU" -- \
        python3 scripts/hil-rates.py

`DEPLOYWATCH` names the binary (default: the test build's,
scripts/deploywatch-bin.py). Exits 1 when a run at up to 250 Hz is not
counted exactly or not bit-identical (at 500 Hz and 1 kHz the link itself,
QEMU's UART, is the limit: docs/firmware.md "What sets the latency").
"""

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
T01_RUN = "data/examples/a_seed001_eft/seed001_T01.csv"
T01 = "data/mechanisms/seed001_T01.toml"
T01_1KHZ = "data/reference/seed001_T01_eft.csv"
WING6_RUN = "data/examples/wing6/wing6_ideal.csv"
WING6 = "data/mechanisms/wing6_ideal.toml"

# (label, run, mechanism, extra arguments, must be exact)
RUNS = [
    ("`a_seed001_eft/seed001_T01.csv`, 3 joints", T01_RUN, T01, [], True),
    ("the same, `--drop 0.01 --corrupt 0.01 --seed 3`", T01_RUN, T01,
     ["--drop", "0.01", "--corrupt", "0.01", "--seed", "3"], True),
    ("`wing6/wing6_ideal.csv`, 6 joints", WING6_RUN, WING6, [], True),
    ("1 kHz reference run `--every 10`", T01_1KHZ, T01, ["--every", "10"], True),
    ("`--every 5`", T01_1KHZ, T01, ["--every", "5"], True),
    ("`--every 4`", T01_1KHZ, T01, ["--every", "4"], True),
    ("`--every 2`", T01_1KHZ, T01, ["--every", "2"], False),
    ("all 3,915 samples", T01_1KHZ, T01, [], False),
]

PATTERNS = {
    "rate": r"at (\d+) Hz",
    "used": r"firmware: (\d+) samples used, (\d+) corrupted, (\d+) too long, (\d+) bytes overrun: (.*)",
    "shed": r"prediction: slices cut short by a waiting frame after (\d+) of (\d+) samples",
    "same": r"; (\d+) of (\d+) bit-identical",
    "latency": r"median ([\d.]+) ms, p99 ([\d.]+) ms, worst ([\d.]+) ms",
    "misses": r"deadline misses .*: (\d+) of (\d+)",
}


def binary() -> str:
    """The deploywatch binary: `DEPLOYWATCH`, else the test build's."""
    if os.environ.get("DEPLOYWATCH"):
        return os.environ["DEPLOYWATCH"]
    out = subprocess.run([sys.executable, str(ROOT / "scripts" / "deploywatch-bin.py")],
                         cwd=ROOT, check=True, stdout=subprocess.PIPE, text=True)
    return out.stdout.strip()


def load() -> str:
    """The 1-minute load average."""
    return Path("/proc/loadavg").read_text().split()[0]


def main() -> int:
    exe = binary()
    print(f"On `{os.uname().nodename}` ({os.cpu_count()} cores), QEMU TCG without `-icount`; "
          "the load average (1 min) before each run in its row.\n")
    print("| run | rate | load | statuses bit-identical | firmware's counts | "
          "slices yielded after | latency median / p99 / worst | deadline misses |")
    print("|---|---|---|---|---|---|---|---|")
    failed = []
    for label, run, mech, extra, exact in RUNS:
        before = load()
        p = subprocess.run([exe, "hil", run, "--mechanism", mech, *extra], cwd=ROOT,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        got = {k: re.search(v, p.stdout) for k, v in PATTERNS.items()}
        if not all(got.values()):
            sys.stderr.write(p.stdout)
            print(f"| {label} | - | {before} | no verdict (exit {p.returncode}) | | | | |")
            failed.append(label)
            continue
        used = got["used"]
        counts = ("exact" if used[5] == "counted exactly" else
                  f"NOT as sent: {used[1]} used, {used[2]} corrupted, {used[4]} B overrun")
        lat = got["latency"]
        print(f"| {label} | {got['rate'][1]} Hz | {before} | {got['same'][1]} / {got['same'][2]} | "
              f"{counts} | {got['shed'][1]} of {got['shed'][2]} samples | "
              f"{lat[1]} / {lat[2]} / {lat[3]} ms | {got['misses'][1]} of {got['misses'][2]} |")
        if exact and p.returncode != 0:
            failed.append(label)
    if failed:
        sys.stderr.write(f"hil-rates: not exact or not bit-identical: {', '.join(failed)}\n")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
