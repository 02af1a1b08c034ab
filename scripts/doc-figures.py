#!/usr/bin/env python3
"""Fails when a doc holds a measured figure that no script writes or checks.

    python3 scripts/doc-figures.py [--check]     exit 1 on a figure outside docs/measured.md
    python3 scripts/doc-figures.py --self-test   prove the checker fails on planted figures
    python3 scripts/doc-figures.py [...] FILE    only these files

A measured figure (a time, a rate of cases found, an RMS reached, a count
of instructions or bytes used, a c.o.v. — a number a run measured) lives in
one place: a section of docs/measured.md, written by the experiment, bench
or script that measures it, with its command (`<!-- measured:NAME
(COMMAND) -->`). The other docs link there (`measured.md#...`). Two other
places may hold figures: the output blocks that `scripts/doc-examples.py`
runs and compares (a command's shown output), and the dated records of
docs/decisions/ (what was measured when a design was chosen), besides
docs/spec/ (the contract) and CHANGELOG.md (history).

What is flagged, outside fenced blocks of code and outside compared output
blocks (each rule names what it catches):

- a date (`2026-11-25`): a dated figure is a measurement;
- `measured` / `median` / `took` / `wall` next to a number with a unit;
- a number with a time, instruction or byte unit after words that report a
  run (`took`, `takes`, `in`, `at most`, `peak`, `used`);
- `N/M` counts beside words of a result (found, right, named, campaigns,
  cases, runs, clean, exact);
- `X° → Y°` or `RMS X → Y` (an RMS reached);
- a c.o.v. with its value;
- a table with a `measured` (or `found`, `wall time`, `result`) column.

A paragraph, list item or table that holds design numbers caught by a rule
(a budget, a threshold, a parameter of an experiment's design) is marked
by an HTML comment on the line before it, with the reason:

    <!-- doc-figures: not measured (the budgets of scripts/firmware.sh) -->

The comments of the Rust sources (`//`, `///`, `//!` in core/, host-sim/,
tests/, python/src/, firmware-example/src/, fuzz/fuzz_targets/, outside
fenced blocks of a doc comment) are scanned by the same rules: a figure a
run measured is no more true in a comment than in a doc. A design number
there is marked by a comment line `// doc-figures: not measured (reason)`
before it, which covers the comment lines after it.
"""

import importlib.util
import re
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# doc-examples.py knows which blocks it runs and compares.
_spec = importlib.util.spec_from_file_location("doc_examples", ROOT / "scripts" / "doc-examples.py")
doc_examples = importlib.util.module_from_spec(_spec)
sys.modules["doc_examples"] = doc_examples
_spec.loader.exec_module(doc_examples)

NUM = r"\d[\d,]*(?:\.\d+)?(?:e-?\d+)?"
TIME = r"(?:s|ms|µs|us|min|h)"
UNIT = r"(?:s|ms|µs|us|min|%|°|B|KiB|k?B|instructions|M instructions|deployments|simulations)"
# A confidence level (`95 % interval`) is a design number, not a result.
NOT_LEVEL = r"(?!\s+(?:intervals?|confidence|CI)\b)"
RESULT_WORDS = r"(?:found|right|named|campaigns?|cases?|runs right|clean|exact|correct|passed|met)"

RULES = [
    ("a date (a dated figure is a measurement: docs/measured.md)", re.compile(r"\b20\d\d-[01]\d-[0-3]\d\b")),
    (
        "a figure beside `measured`/`median`/`wall`",
        re.compile(
            rf"\b(?:[Mm]easured|[Mm]edian|wall)\b[^.;|]{{0,40}}?(?<![≤≥<>])\s{NUM}\s?{UNIT}(?!\w){NOT_LEVEL}"
            rf"|(?<![≤≥<>]\s){NUM}\s?{TIME}\s+(?:wall|of CPU)\b"
        ),
    ),
    (
        "a time, instruction or byte count a run reported",
        re.compile(
            rf"\b(?:took|takes|take|taking|costs?|ran in|runs in|peak(?: of)?|used|uses|fastest(?: of \d+ runs)?:?)\s+"
            rf"(?:about |at most |up to )?{NUM}\s?(?:{TIME}|instructions|B|KiB)(?!\w)"
        ),
    ),
    ("an N/M count of a result", re.compile(rf"(?<![\w./-])\d{{1,5}}\s?/\s?\d{{1,5}}(?![\w./])(?=[^.|]{{0,60}}\b{RESULT_WORDS})|\b{RESULT_WORDS}\b[^.|]{{0,30}}(?<![\w./-])\d{{1,5}}\s?/\s?\d{{1,5}}(?![\w./])")),
    (
        "bytes of flash, RAM or stack used",
        re.compile(
            rf"(?<![≤<=]\s)(?<![≤<=]){NUM}\s?(?:B|bytes)\s+of\s+(?:the\s+)?(?:firmware's\s+)?(?:flash|static RAM|RAM|stack)\b"
        ),
    ),
    ("an RMS reached (X → Y)", re.compile(rf"{NUM}\s?°?\s?(?:RMS\s)?→\s?{NUM}")),
    ("a c.o.v. with its value", re.compile(rf"c\.o\.v\.?\s*(?:of\s+|=\s*|:\s*)?(?<![≤<])\s?{NUM}")),
]
TABLE_HEAD = re.compile(r"^\|.*\b(measured|found|wall time|result)\b.*\|\s*$", re.I)
ALLOW = re.compile(r"^\s*<!--\s*doc-figures:\s*not measured\s*\((.+)\)\s*-->\s*$")
# Sections whose figures another change moves into docs/measured.md (the
# experiment that writes them is being converted): reported, not failed.
# Remove an entry when its section links to measured.md.
PENDING: dict = {}
CODE_INFOS = {"sh", "bash", "shell", "rust", "toml", "python", "json", "csv", "layers", "yaml", "ini", "c", "text"}


def checked_lines(lines):
    """0-based indices of lines in fenced blocks: code, or output that doc-examples compares.

    A `text` / unlabelled block is skipped only when doc-examples runs and
    compares it (a command's output, a transcript of run commands) or it is a
    command or synopsis block; any other plain block (a pasted output) is
    scanned."""
    skip = set()
    for b in doc_examples.classify(lines):
        compared = (b.output_of is not None and any(c.kind == "run" for c in b.output_of.commands)) or (
            b.transcript and any(c.kind == "run" for c in b.commands)
        )
        plain = b.info in ("", "text")
        if not plain or compared or b.commands:
            skip.update(range(b.start, b.end + 1))
        else:
            skip.update((b.start, b.end))
    return skip


def allowed_lines(lines):
    """Lines covered by a `doc-figures: not measured` marker: the paragraph,
    list item or table after it (up to the next blank line)."""
    out, i = set(), 0
    while i < len(lines):
        if ALLOW.match(lines[i]):
            j = i + 1
            while j < len(lines) and lines[j].strip():
                out.add(j)
                j += 1
            i = j
        else:
            i += 1
    return out


def strip_inline(line):
    """The line without `code spans`, links' targets and HTML comments."""
    line = re.sub(r"`[^`]*`", "``", line)
    line = re.sub(r"\]\([^)]*\)", "]()", line)
    return re.sub(r"<!--.*?-->", "", line)


RUST_COMMENT = re.compile(r"^\s*//[/!]?\s?(.*)$")
RUST_ALLOW = re.compile(r"^\s*//[/!]?\s*doc-figures:\s*not measured\s*\((.+)\)\s*$")


def scan_rust(path):
    """(line, rule, text) of every measured figure in the comments of a Rust
    source: outside the fenced blocks of its doc comments, and outside the
    comment lines a `// doc-figures: not measured (reason)` line covers."""
    hits, fence, allowed = [], False, False
    for i, raw in enumerate(Path(path).read_text(encoding="utf-8").splitlines()):
        m = RUST_COMMENT.match(raw)
        if not m:
            allowed = False
            continue
        if RUST_ALLOW.match(raw):
            allowed = True
            continue
        text = m.group(1)
        if text.strip().startswith("```"):
            fence = not fence
            continue
        if fence or allowed:
            continue
        line = strip_inline(text)
        for why, rule in RULES:
            if rule.search(line):
                hits.append((i + 1, why, text.strip()))
                break
    return hits


def scan(path):
    """(line, rule, text) of every measured figure outside docs/measured.md's kind of place."""
    if str(path).endswith(".rs"):
        return scan_rust(path)
    text = Path(path).read_text(encoding="utf-8")
    lines = text.splitlines()
    md = str(path).endswith(".md")
    skip = checked_lines(lines) if md else set()
    allow = allowed_lines(lines) if md else set()
    hits = []
    in_table_measured = False
    rel = str(Path(path).resolve().relative_to(ROOT)) if str(Path(path).resolve()).startswith(str(ROOT)) else str(path)
    section = ""
    for i, raw in enumerate(lines):
        if raw.startswith("## "):
            section = raw.strip()
        if (rel, section) in PENDING:
            continue
        if i in skip:
            in_table_measured = False
            continue
        if md and raw.startswith("|"):
            if TABLE_HEAD.match(raw) and (i + 1 < len(lines) and re.match(r"^\|[-:| ]+\|\s*$", lines[i + 1])):
                in_table_measured = i not in allow
                continue
        else:
            in_table_measured = False
        if i in allow:
            continue
        line = strip_inline(raw)
        if in_table_measured and not re.match(r"^\|[-:| ]+\|\s*$", raw) and re.search(r"\d", line):
            hits.append((i + 1, "a row of a table with a measured column", raw.strip()))
            continue
        for why, rule in RULES:
            if rule.search(line):
                hits.append((i + 1, why, raw.strip()))
                break
    return hits


def default_files():
    files = [ROOT / "README.md", ROOT / "ARCHITECTURE.md"]
    files += sorted(p for p in (ROOT / "docs").glob("*.md") if p.name != "measured.md")
    files += sorted(ROOT.glob("*/README.md"))
    files += sorted(ROOT.glob("*/Cargo.toml")) + [ROOT / "Cargo.toml"]
    files += [ROOT / "memory.x"] + sorted(ROOT.glob("firmware-example/*.x"))
    for d in ("core", "host-sim", "tests", "python/src", "firmware-example/src", "fuzz/fuzz_targets"):
        files += sorted(p for p in (ROOT / d).rglob("*.rs") if "target" not in p.relative_to(ROOT).parts)
    return [f for f in files if f.exists()]


def check(files):
    for (doc, heading), why in PENDING.items():
        print(f"pending: {doc} \"{heading[3:]}\": {why}")
    n = 0
    for f in files:
        for line, why, text in scan(f):
            rel = f.relative_to(ROOT) if str(f).startswith(str(ROOT)) else f
            print(f"{rel}:{line}: {why}: {text[:160]}", file=sys.stderr)
            n += 1
    return n


PLANTED = [
    "The suite found 61/61 campaigns.",
    "Measured 2026-11-27 on two cores.",
    "The diagnosis took 4.16 s on campaign (a).",
    "`update` peak 4,400 instructions at worst: it took 4,400 instructions.",
    "The fit went from 43.20° → 0.0216°.",
    "Subset simulation reached c.o.v. 0.34.",
    "The physical rule costs 180 B of flash.",
    "The median is 1.43 s.",
    "| example | wall time |\n|---|---|\n| (a) | 5.00 s |",
]
CLEAN = [
    "Each hidden effect moves the runs by at least 0.3° RMS.",
    "The budget is ≤ 4,400 instructions per sample at 100 Hz.",
    "The measured figures are in [measured.md](measured.md#monitor-refresh).",
    "<!-- doc-figures: not measured (a threshold) -->\nThe CI asserts ≥ 60 % found and 6/6 campaigns.",
    "```text\nmedian 1.43 s wall\n```",
    "The measured median with its 95 % interval.",
]


def self_test():
    problems = []
    tmp = Path(tempfile.mkdtemp(prefix="doc-figures-"))
    for k, planted in enumerate(PLANTED):
        p = tmp / f"planted{k}.md"
        p.write_text(f"# A doc\n\nSome design.\n\n{planted}\n")
        if not scan(p):
            problems.append(f"a planted figure passed: {planted!r}")
    for k, clean in enumerate(CLEAN):
        p = tmp / f"clean{k}.md"
        p.write_text(f"# A doc\n\n{clean}\n")
        hits = scan(p)
        if hits and "```text" not in clean:
            problems.append(f"a design number was flagged: {clean!r}: {hits}")
    # A Rust comment is scanned; a doc comment's fenced block and a marked
    # comment are not.
    p = tmp / "planted.rs"
    p.write_text("//! postcard's reader took 0.7 KiB of flash.\nfn f() {}\n")
    if not scan(p):
        problems.append("a figure in a Rust comment passed")
    p = tmp / "clean.rs"
    p.write_text(
        "/// ```text\n/// median 1.43 s\n/// ```\n"
        "// doc-figures: not measured (a budget)\n// It took 4,400 instructions at most.\nfn f() {}\n"
    )
    if scan(p):
        problems.append(f"a Rust comment's fenced block or marked line was flagged: {scan(p)}")
    # A pasted output (a text block no command produces) is scanned.
    p = tmp / "pasted.md"
    p.write_text("# A doc\n\n```text\nmedian 1.43 s\n```\n")
    if not scan(p):
        problems.append("a pasted output block no command produces passed")
    for p in problems:
        print(f"self-test FAILED: {p}", file=sys.stderr)
    if not problems:
        print(f"self-test passed: {len(PLANTED)} planted figures fail, {len(CLEAN)} design numbers pass")
    return not problems


def main():
    args = sys.argv[1:]
    if any(a in ("-h", "--help") for a in args):
        print(__doc__)
        return
    if "--self-test" in args:
        sys.exit(0 if self_test() else 1)
    files = [Path(f).resolve() for f in args if f != "--check"] or default_files()
    n = check(files)
    if n:
        print(f"\n{n} measured figure(s) outside docs/measured.md: move each into a section written by the "
              "script that measures it and link to it, or mark design numbers "
              "(`<!-- doc-figures: not measured (reason) -->`)", file=sys.stderr)
        sys.exit(1)
    print(f"no measured figure outside docs/measured.md in {len(files)} files")


if __name__ == "__main__":
    main()
