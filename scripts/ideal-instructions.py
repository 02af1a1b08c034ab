#!/usr/bin/env python3
"""Where an ideal-latch deployment's instructions go, counted by callgrind.

Runs `examples/ideal_profile.rs` (seed 001 T01, its identified friction at
5 % lognormal dispersion, its three rows of ledger tolerance) under
`valgrind --tool=callgrind` and prints the instructions per deployment, in
total and inclusive of the functions that take them. Instruction counts do
not depend on the machine's load, where the CPU times of `ideal_profile`
move by a third on a shared machine.

    scripts/ideal-instructions.py [DRAWS]    (default 200; needs valgrind)
"""
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROWS = 3  # ideal_profile's rows: the verdict's ledger, the reference's, none

# Name in the table -> what the function's name ends with in callgrind's
# `file:function` lines (inlined code is listed under other files too; the
# largest inclusive count of a function is its own).
FUNCTIONS = [
    ("equations of motion (`Chain::acceleration_with_torques`)", "Chain<T,_,_>::acceleration_with_torques"),
    ("  the spring's torque (`Spring::torque`)", "Spring<T>::torque"),
    ("  libm `tanh` (with its `expm1`: the friction laws)", "libm::math::tanh::tanh"),
    ("  the solve (`solve_spd_masked`)", "linalg::solve_spd_masked"),
    ("libm `sincos` (the equations' and the kinetic energy's)", "libm::math::sincos::sincos"),
    ("the ledger's power (`chain_ledger::power`)", "chain_ledger::power"),
    ("the ledger's booking (`ChainLedger::book`)", "ChainLedger::book"),
    ("  the potential energy", "Chain<T,_,_>::potential_energy"),
    ("  the kinetic energy", "Chain<T,_,_>::kinetic_energy"),
    ("the step controller's `pow` (glibc)", "pow@@GLIBC_2.29"),
]


def main():
    draws = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    subprocess.run(
        ["cargo", "build", "-q", "--release", "-p", "deploywatch-sim", "--example", "ideal_profile"],
        cwd=ROOT,
        check=True,
    )
    out = os.path.join(ROOT, "target", "ideal-instructions.callgrind")
    run = subprocess.run(
        [
            "valgrind",
            "--tool=callgrind",
            f"--callgrind-out-file={out}",
            os.path.join(ROOT, "target", "release", "examples", "ideal_profile"),
            str(draws),
        ],
        capture_output=True,
        text=True,
    )
    if run.returncode != 0:
        sys.stderr.write(run.stdout + run.stderr)
        sys.exit(run.returncode)
    table = subprocess.run(
        ["callgrind_annotate", "--inclusive=yes", "--threshold=100", out],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    total = None
    inclusive = {}
    for line in table.splitlines():
        m = re.match(r"\s*([\d,]+) \(\s*[\d.]+%\)\s+(.*)", line)
        if not m:
            continue
        count, what = int(m.group(1).replace(",", "")), m.group(2)
        if what.startswith("PROGRAM TOTALS"):
            total = count
            continue
        name = re.sub(r"\s*\[[^]]*\]$", "", what)
        for _, suffix in FUNCTIONS:
            if name.endswith(suffix):
                inclusive[suffix] = max(inclusive.get(suffix, 0), count)
    if not total:
        sys.exit("ideal-instructions: no program total in callgrind's output")
    deployments = ROWS * draws
    print(f"`ideal_profile {draws}` under callgrind: {deployments} deployments of seed001_T01 "
          f"({ROWS} rows of {draws} draws), {total:,} instructions, "
          f"{total // deployments:,} per deployment.\n")
    print("| inclusive of | instructions per deployment | share |")
    print("|---|---|---|")
    for label, suffix in FUNCTIONS:
        count = inclusive.get(suffix, 0)
        print(f"| {label} | {count // deployments:,} | {100.0 * count / total:.1f} % |")
    print("\nThe rows of `ideal_profile` (its CPU columns, valgrind's, left out):\n")
    for line in run.stdout.splitlines():
        if line.startswith("|"):
            print("|".join(line.split("|")[:7]) + "|")


if __name__ == "__main__":
    main()
