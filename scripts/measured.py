#!/usr/bin/env python3
"""Writes measured figures into docs/measured.md, one section per measurement.

Each section of docs/measured.md lies between
`<!-- measured:NAME (COMMAND) -->` and `<!-- /measured:NAME -->` and is
rewritten only by the script that measures it; no one edits it by hand, and
no other doc repeats its figures (they link to it).

    scripts/measured.py firmware-size JOINTS:FLASH:RAM:FLASH_BUDGET:RAM_BUDGET...
        (one per replay firmware, the first the default one)
        (called by scripts/firmware.sh size / build / test)
    scripts/measured.py firmware-replays DIR UPDATE_BUDGET UPDATE_BUDGET_PHYSICAL SLICE_BUDGET STACK_BUDGET
        (called by scripts/firmware.sh test: DIR/*/replay.log, the
        firmware's log of each replay; exits 1 when a budget is not met)
    scripts/measured.py bench NAME LOG
        (called by scripts/bench.sh NAME: criterion's estimates under
        target/criterion of the benchmarks LOG names, and the lines the
        bench printed before timing — its accuracy check)
    scripts/measured.py diagnose-times LOG
        (called by scripts/bench-diagnose.sh: its printed wall times)
    scripts/measured.py run NAME "TITLE" -- COMMAND...
        (any experiment that prints its figures: runs COMMAND, exits with
        its status on failure, else writes its stdout as section NAME,
        headed TITLE, the command beside it)
    scripts/measured.py check
        (every section has its command and its date; every link to
        measured.md#ANCHOR from another doc names a heading of it)
"""
import datetime
import glob
import json
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


def firmware_size(*elves):
    rows = []
    for e in elves:
        joints, flash, ram, fb, rb = map(int, e.split(":"))
        memory = "`memory.x`" if rb == 16384 else f"`memory-{joints}.x`"
        rows.append(f"| {joints} | flash (.text + .data) | {n(flash)} B | {n(fb)} B ({memory}) | {n(fb - flash)} B |")
        rows.append(f"| {joints} | static RAM (.data + .bss) | {n(ram)} B | {n(rb)} B | "
                    f"{n(rb - ram)} B (the stack uses the rest) |")
    body = """## Firmware: flash and RAM

One replay firmware per joint count (the monitor's `N` is the binary's,
`firmware-example/Cargo.toml`).

| joints | region | used | budget | left |
|---|---|---|---|---|
""" + "\n".join(rows) + "\n"
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
    # The budgets hold for monitors of up to 3 joints; larger ones are
    # measured and stated (their worst figures, no budget).
    larger = {}
    for log in sorted(glob.glob(os.path.join(folder, "*", "replay.log"))):
        name = os.path.basename(os.path.dirname(log))
        got = parse_log(log)
        if "Monitor::update" not in got or "predict" not in got:
            continue
        physical = name.startswith("latch_")
        _, um, ux = got["Monitor::update"]
        _, pm, px = got["predict"]
        stack = got.get("stack", 0)
        joints = got.get("joints", 0)
        if joints > 3:
            w = larger.setdefault(joints, [0, 0, 0])
            w[0], w[1], w[2] = max(w[0], ux), max(w[1], px), max(w[2], stack)
        else:
            kind = "physical" if physical else "ideal"
            worst[kind] = max(worst[kind], ux)
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
    stated = "".join(
        f"| {j} joints: `Monitor::update` max / `predict` slice max / stack peak | (stated) | "
        f"{n(u)} instructions / {n(p)} instructions / {n(st)} B |\n"
        for j, (u, p, st) in sorted(larger.items()))
    body = f"""## Monitor on the Cortex-M4F: instructions and stack

Instructions counted under QEMU (`-icount shift=3`: 5 instructions a SysTick tick, read around
each call) over whole replays, checked bit-identical with the host; the
budgets are those of `scripts/firmware.sh`, for monitors of up to 3 joints;
larger ones are measured and stated.

| measure | budget | measured |
|---|---|---|
{table}
{stated}
| replay | joints | `update` mean | `update` max | `predict` slice mean | `predict` slice max | stack peak |
|---|---|---|---|---|---|---|
""" + "\n".join(rows) + "\n"
    write_section("firmware-replays", "scripts/firmware.sh test", body)
    if any(v > b for _, v, b, _ in checks):
        sys.exit("measured.py: a budget of the monitor is not met (docs/measured.md)")


# bench: (section, heading, target, deployments per iteration or None)
BENCHES = {
    "simulate": ("bench-simulate", "Bench: one chain deployment", "≤ 1 ms median", None),
    "truss": ("bench-truss", "Bench: truss wing", "≤ 5 ms median", None),
    "reliability": ("bench-reliability", "Bench: reliability deployments", "(reported)", 200),
}
CRITERION_NOISE = re.compile(
    r"^\s*(Benchmarking|Gnuplot|Found \d+ outliers|\s+\d+ \(|\s+time:|\s+change:|\s+thrpt:|Performance has|"
    r"No change in|Change within|Warning|WARNING|\s*$|\s*Running|\s*Compiling|\s*Finished|\s*Blocking|running \d+ tests|test result)"
)


def human_time(ns):
    """A criterion time [ns] with its unit."""
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


def criterion_estimates(root, full_id):
    """(median, lower, upper) [ns] of the benchmark `full_id` under `root`."""
    for bj in glob.glob(os.path.join(root, "**", "new", "benchmark.json"), recursive=True):
        with open(bj, encoding="utf-8") as f:
            if json.load(f).get("full_id") != full_id:
                continue
        with open(os.path.join(os.path.dirname(bj), "estimates.json"), encoding="utf-8") as f:
            med = json.load(f)["median"]
        ci = med["confidence_interval"]
        return med["point_estimate"], ci["lower_bound"], ci["upper_bound"]
    return None


def bench(name, log):
    if name not in BENCHES:
        sys.exit(f"measured.py: no bench {name!r} (one of {', '.join(BENCHES)})")
    section, title, target, per = BENCHES[name]
    lines = open(log, encoding="utf-8", errors="replace").read().splitlines()
    ids = []
    for line in lines:
        m = re.match(r"^Benchmarking (.+): Analyzing", line)
        if m and m.group(1) not in ids:
            ids.append(m.group(1))
    rows = []
    for full_id in ids:
        got = criterion_estimates(os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "criterion"), full_id)
        if got:
            med, lo, hi = got
            rate = f"; {per / (med * 1e-9):,.0f} deployments per core-second" if per else ""
            rows.append(f"| {full_id} | {target} | **{human_time(med)}** (95 % CI {human_time(lo)}–{human_time(hi)}){rate} |")
    if not rows:
        sys.exit(f"measured.py: no criterion estimate for the benchmarks of {log}")
    printed = [line for line in lines if not CRITERION_NOISE.match(line) and line.strip() not in ids]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    body = f"""## {title}

Criterion's median (`cargo bench -p deploywatch-sim --bench {name}`), load
average {load:.1f} on this machine's cores when written (times are upper
bounds on a shared machine); below the table, what the bench printed before
timing (its check against the golden files), if anything.

| benchmark | target | median |
|---|---|---|
""" + "\n".join(rows) + "\n"
    if "\n".join(printed).strip():
        body += "\n```text\n" + "\n".join(printed).strip() + "\n```\n"
    write_section(section, f"scripts/bench.sh {name}", body)


def diagnose_times(log):
    rows, median = [], None
    for line in open(log, encoding="utf-8"):
        m = re.match(r"^(\S+): ([\d.]+) s \((.*)\)$", line.strip())
        if m:
            rows.append(f"| {m.group(1)} | {m.group(2)} s | {m.group(3)} |")
        m = re.match(r"^median of the two-run campaigns: ([\d.]+) s", line.strip())
        if m:
            median = m.group(1)
    if not rows or median is None:
        sys.exit(f"measured.py: no wall times in {log}")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    body = f"""## Diagnose: wall time

`deploywatch diagnose` (release build, wall time of the whole command,
report plots included) on the campaigns of `scripts/bench-diagnose.sh`,
load average {load:.1f} on this machine's cores when written (times are
upper bounds on a shared machine); targets: median of the two-run
campaigns ≤ 10 s, the 10-run campaign ≤ 60 s.

| campaign | wall time | first line of the output |
|---|---|---|
""" + "\n".join(rows) + f"\n\nMedian of the two-run campaigns: **{median} s**.\n"
    write_section("diagnose-wall-time", "scripts/bench-diagnose.sh", body)


def slug(heading):
    """GitHub's anchor of a heading."""
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def check():
    """Each section carries its command and date; links into measured.md resolve."""
    text = open(DOC, encoding="utf-8").read()
    problems = []
    opens = re.findall(r"<!-- measured:([\w-]+) \((.+?)\) -->", text)
    for name, command in opens:
        end = f"<!-- /measured:{name} -->"
        if end not in text:
            problems.append(f"section {name}: no end marker")
            continue
        block = text[text.index(f"<!-- measured:{name} "):text.index(end)]
        if not re.search(rf"_Measured \d{{4}}-\d\d-\d\d by `{re.escape(command)}`", block):
            problems.append(f"section {name}: no line `_Measured DATE by `{command}`._`")
        if "\n## " not in block:
            problems.append(f"section {name}: no `## ` heading")
    if len({n for n, _ in opens}) != len(opens):
        problems.append("a section name is used twice")
    anchors = {slug(h) for h in re.findall(r"^## (.+)$", text, re.M)}
    docs = [os.path.join(ROOT, "README.md"), os.path.join(ROOT, "ARCHITECTURE.md")]
    docs += glob.glob(os.path.join(ROOT, "docs", "*.md")) + glob.glob(os.path.join(ROOT, "docs", "decisions", "*.md"))
    docs += glob.glob(os.path.join(ROOT, "*", "README.md"))
    for d in docs:
        for anchor in re.findall(r"measured\.md#([\w-]+)", open(d, encoding="utf-8").read()):
            if anchor not in anchors:
                problems.append(f"{os.path.relpath(d, ROOT)}: measured.md#{anchor} names no heading of docs/measured.md")
    for p in problems:
        print(f"measured.py check: {p}", file=sys.stderr)
    if problems:
        sys.exit(1)
    print(f"docs/measured.md: {len(opens)} sections, each with its command and date; every link resolves")


def run(name, title, command):
    """Runs `command` (a list) and writes its stdout as section `name`."""
    import shlex
    import subprocess

    r = subprocess.run(command, cwd=ROOT, stdout=subprocess.PIPE, text=True)
    sys.stdout.write(r.stdout)
    if r.returncode != 0:
        sys.exit(f"measured.py: `{shlex.join(command)}` exited {r.returncode}; docs/measured.md left as it is")
    shown = shlex.join(command)
    body = f"""## {title}

The output of `{shown}`:

```text
{r.stdout.strip()}
```
"""
    write_section(name, f"scripts/measured.py run {name} \"{title}\" -- {shown}", body)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd == "firmware-size" and args:
        firmware_size(*args)
    elif cmd == "firmware-replays" and len(args) == 5:
        firmware_replays(*args)
    elif cmd == "bench" and len(args) == 2:
        bench(*args)
    elif cmd == "diagnose-times" and len(args) == 1:
        diagnose_times(*args)
    elif cmd == "run" and len(args) >= 4 and args[2] == "--":
        run(args[0], args[1], args[3:])
    elif cmd == "check" and not args:
        check()
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
