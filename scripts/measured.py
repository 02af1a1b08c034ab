#!/usr/bin/env python3
"""Writes measured figures into docs/measured.md, one section per measurement.

Each section of docs/measured.md lies between
`<!-- measured:NAME (COMMAND) -->` and `<!-- /measured:NAME -->` and is
rewritten only by the script that measures it; no one edits it by hand, and
no other doc repeats its figures (they link to it).

    scripts/measured.py firmware-size FLASH RAM FLASH_BUDGET RAM_BUDGET
        (called by scripts/firmware.sh size / build / test)
    scripts/measured.py firmware-replays DIR UPDATE_BUDGET UPDATE_BUDGET_PHYSICAL SLICE_BUDGET STACK_BUDGET
        (called by scripts/firmware.sh test: DIR/*/replay.log, the
        firmware's log of each replay; exits 1 when a budget is not met)
"""
import datetime
import glob
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "measured.md")

HEAD = """# Measured figures

Every figure here is written by the script that measures it, with the
command that reruns it; the other docs link here instead of repeating a
number. Do not edit the sections by hand: rerun the command.
"""


def n(x):
    """An integer with thousands separators (4,240)."""
    return f"{x:,}"


def write_section(name, command, body):
    text = open(DOC, encoding="utf-8").read() if os.path.exists(DOC) else HEAD
    start = f"<!-- measured:{name} "
    end = f"<!-- /measured:{name} -->"
    date = datetime.date.today().isoformat()
    block = f"{start}({command}) -->\n{body.rstrip()}\n\n_Measured {date} by `{command}`._\n{end}"
    if start in text and end in text:
        a = text.index(start)
        b = text.index(end) + len(end)
        text = text[:a] + block + text[b:]
    else:
        text = text.rstrip() + "\n\n" + block + "\n"
    with open(DOC, "w", encoding="utf-8") as f:
        f.write(text if text.endswith("\n") else text + "\n")


def firmware_size(flash, ram, flash_budget, ram_budget):
    flash, ram, fb, rb = map(int, (flash, ram, flash_budget, ram_budget))
    body = f"""## Firmware: flash and RAM

| region | used | budget (`memory.x`) | left |
|---|---|---|---|
| flash (.text + .data) | {n(flash)} B | {n(fb)} B | {n(fb - flash)} B |
| static RAM (.data + .bss) | {n(ram)} B | {n(rb)} B | {n(rb - ram)} B (the stack uses the rest) |
"""
    write_section("firmware-size", "scripts/firmware.sh size", body)


LINE = re.compile(r"(Monitor::update|predict): (\d+) calls, mean (\d+) max (\d+) instructions")
STACK = re.compile(r"stack: peak (\d+) B of (\d+) B")
JOINTS = re.compile(r"monitor of (\d+) joints")


def parse_log(path):
    got = {}
    for line in open(path, encoding="utf-8", errors="replace"):
        m = LINE.search(line)
        if m:
            got[m.group(1)] = (int(m.group(2)), int(m.group(3)), int(m.group(4)))
        m = STACK.search(line)
        if m:
            got["stack"] = int(m.group(1))
        m = JOINTS.search(line)
        if m:
            got["joints"] = int(m.group(1))
    return got


def firmware_replays(folder, update_budget, update_budget_physical, slice_budget, stack_budget):
    budgets = list(map(int, (update_budget, update_budget_physical, slice_budget, stack_budget)))
    rows, worst = [], {"ideal": 0, "physical": 0, "slice": 0, "stack": 0}
    for log in sorted(glob.glob(os.path.join(folder, "*", "replay.log"))):
        name = os.path.basename(os.path.dirname(log))
        got = parse_log(log)
        if "Monitor::update" not in got or "predict" not in got:
            continue
        physical = name.startswith("latch_")
        _, um, ux = got["Monitor::update"]
        _, pm, px = got["predict"]
        stack = got.get("stack", 0)
        worst["physical" if physical else "ideal"] = max(worst["physical" if physical else "ideal"], ux)
        worst["slice"] = max(worst["slice"], px)
        worst["stack"] = max(worst["stack"], stack)
        rows.append(f"| {name}{' (physical latch)' if physical else ''} | {got.get('joints', '?')} | "
                    f"{n(um)} | {n(ux)} | {n(pm)} | {n(px)} | {n(stack)} B |")
    if not rows:
        sys.exit(f"measured.py: no replay log with instruction counts under {folder}")
    checks = [
        ("`Monitor::update`, worst, ideal latches", worst["ideal"], budgets[0], "instructions"),
        ("`Monitor::update`, worst, physical latch", worst["physical"], budgets[1], "instructions"),
        ("`predict` slice, worst", worst["slice"], budgets[2], "instructions"),
        ("stack peak", worst["stack"], budgets[3], "B"),
    ]
    table = "\n".join(
        f"| {what} | ≤ {n(b)} {unit} | **{n(v)} {unit}: {'met' if v <= b else 'NOT met'}** |"
        for what, v, b, unit in checks)
    body = f"""## Monitor on the Cortex-M4F: instructions and stack

Instructions counted under QEMU (`-icount shift=0`, SysTick read around
each call) over whole replays, checked bit-identical with the host; the
budgets are those of `scripts/firmware.sh`.

| measure | budget | measured |
|---|---|---|
{table}

| replay | joints | `update` mean | `update` max | `predict` slice mean | `predict` slice max | stack peak |
|---|---|---|---|---|---|---|
""" + "\n".join(rows) + "\n"
    write_section("firmware-replays", "scripts/firmware.sh test", body)
    if any(v > b for _, v, b, _ in checks):
        sys.exit("measured.py: a budget of the monitor is not met (docs/measured.md)")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd == "firmware-size" and len(args) == 4:
        firmware_size(*args)
    elif cmd == "firmware-replays" and len(args) == 5:
        firmware_replays(*args)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
