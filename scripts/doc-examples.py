#!/usr/bin/env python3
"""Checks every command shown in README.md and docs/*.md against today's
`deploywatch`, and its shown output against today's output.

    python3 scripts/doc-examples.py [--check]     compare (default); exit 1 on a difference
    python3 scripts/doc-examples.py --update      rewrite the shown outputs from today's run
    python3 scripts/doc-examples.py --self-test   prove the checker fails on a wrong doc
    python3 scripts/doc-examples.py --list        what would be run, checked or skipped; runs nothing
    python3 scripts/doc-examples.py [...] FILE.md only these files

The binary is the one `cargo test --workspace` builds (scripts/deploywatch-bin.py
prints its path, building what is missing).

What is a command, and what is done with it:

- Commands are the lines of a fenced block labelled `sh` (a trailing `\\`
  continues a line, `# ...` is a comment), and the `$ ` lines of a `text`
  or unlabelled block that starts with `$ ` (a transcript: the lines after
  a command, up to the next `$ `, are its shown output). A `text` or
  unlabelled block that starts with `deploywatch ` is a synopsis block.
  `cargo run --release -p deploywatch-sim --` counts as `deploywatch`.
- A command with placeholders (an upper-case word such as `M1.toml`,
  `RUN.csv`, `SPEC`; `...`; `[optional]` parts) is a **synopsis**: not run,
  but each `deploywatch SUBCOMMAND` in it must exist and each of its
  `--flag`s must appear in `deploywatch SUBCOMMAND --help`.
- A command marked in the doc by an HTML comment right before its block is
  **skipped**, and the reason printed:
      <!-- doc-examples: skip (reason) -->              the whole block
      <!-- doc-examples: skip `PREFIX` (reason) -->     the commands starting with PREFIX
- A command that runs no `deploywatch` (`cargo test`, `scripts/...`, a
  Python line) is a **reference**: not run, as it may take minutes or need
  the embedded toolchain, unless the doc opts it in with
      <!-- doc-examples: run `PREFIX` (reason) -->
  (`mkdir` lines are run: later commands write into the folder).
- Synopses, skipped commands and references are checked without running
  them: each `deploywatch SUBCOMMAND` in them must exist and each of its
  `--flag`s appear in `deploywatch SUBCOMMAND --help`; every repository path
  they name (`scripts/...`, `data/...`), every `--test`, `--bench`,
  `--example` target and every `-p` package must exist.
- Every other command is **run**, in the doc's order, with `bash -e` in one
  temporary directory per doc that links every top-level entry of the
  repository (so `data/...` resolves and outputs such as `out/` or `t02.csv`
  land in the temporary directory), `deploywatch` on the PATH. It must exit
  0. If a `text` or unlabelled block follows its `sh` block with only blank
  lines between, that block is the shown stdout of the block's run
  commands (stderr, where progress goes, is never compared); it must equal
  today's stdout after the masks below.
"""

import argparse
import difflib
import glob
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# Run-dependent figures, masked in both the shown and today's output before
# comparing. Each is narrow on purpose: any other number that changes is a
# doc that is out of date. (regex, replacement, why)
MASKS = [
    (
        re.compile(r"\bin \d+(?:\.\d+)? s\b"),
        "in <wall> s",
        'wall time of diagnose and identify ("637 simulations in 0.86 s")',
    ),
    (
        re.compile(r"\b\d+(?:\.\d+)? s wall\b"),
        "<wall> s wall",
        'wall time of reliability and scripts/reliability-closed-form.sh ("0.22 s wall")',
    ),
]

# Top-level folders of the repository: a token of a skipped or synopsis
# command that starts with one of them is a path that must exist.
REPO_DIRS = (
    "core/",
    "data/",
    "docs/",
    "experiments/",
    "firmware-example/",
    "fuzz/",
    "host-sim/",
    "python/",
    "scripts/",
    "tests/",
)

# Longest a run command may take before the checker gives up on it [s].
COMMAND_TIMEOUT_S = 300

MARKER = re.compile(r"^\s*<!--\s*doc-examples:\s*(skip|run)\s*(?:`([^`]+)`)?\s*\((.+)\)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(```+|~~~+)\s*([\w+-]*)\s*$")
CARGO_RUN = re.compile(r"cargo run (?:--release |-q |--quiet )*-p deploywatch-sim(?: --release)? --(?=\s)")
# `deploywatch SUB` at a command position (start, after ; && || | ( do then,
# or a path to the binary such as target/release/deploywatch).
INVOCATION = re.compile(r"(?:^|(?<=[\s;&|(]))(?:[\w./-]*/)?deploywatch\s+([a-z][\w-]*)")
PLACEHOLDER_WORD = re.compile(r"^[A-Z][A-Z0-9_]*(?:\.[a-z]+)?$")
COMMAND_WORDS = ("cargo ", "scripts/", "bash ", "mkdir ", "for ", "python", ".venv/")


@dataclass
class Command:
    """One logical command line of a doc."""

    line: int  # 1-based line of the doc where it starts
    shown: list  # the doc's lines, as written (with `$ ` and continuations)
    text: str  # the command, continuations joined, comment removed
    kind: str = "run"  # run | synopsis | skip | ref
    reason: str = ""
    output_lines: tuple = ()  # transcript: (first, last) line indices of its output, 0-based
    stdout: str = None  # today's stdout, once run with exit 0


@dataclass
class Block:
    """A fenced block: lines[start] is the opening fence, lines[end] the closing one (0-based)."""

    start: int
    end: int
    info: str
    body: list
    markers: list = field(default_factory=list)  # (skip|run, prefix or None, reason)
    commands: list = field(default_factory=list)
    transcript: bool = False
    output_of: "Block" = None  # this block is the shown output of that command block


@dataclass
class Failure:
    path: str
    line: int
    command: str
    message: str


def fail_text(f):
    return f"{f.path}:{f.line}: {f.command}\n{f.message}"


# ---------------------------------------------------------------- parsing


def parse_blocks(lines):
    """Fenced blocks of a Markdown file, with the skip markers before each."""
    blocks, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence, info = m.group(2), m.group(3)
        j = i + 1
        while j < len(lines) and not lines[j].strip().startswith(fence[:3]):
            j += 1
        block = Block(start=i, end=j, info=info, body=lines[i + 1 : j])
        k = i - 1
        while k >= 0 and (not lines[k].strip() or MARKER.match(lines[k])):
            mm = MARKER.match(lines[k])
            if mm:
                block.markers.append((mm.group(1), mm.group(2), mm.group(3)))
            k -= 1
        blocks.append(block)
        i = j + 1
    return blocks


def strip_comment(line):
    """The line without a `# comment` outside quotes."""
    quote = None
    for n, c in enumerate(line):
        if quote:
            if c == quote:
                quote = None
        elif c in "'\"":
            quote = c
        elif c == "#" and (n == 0 or line[n - 1].isspace()):
            return line[:n].rstrip()
    return line.rstrip()


def logical_commands(body, first_line, prompt):
    """Commands of a block: (line, shown lines, text, index of the last shown line).

    With `prompt`, only lines starting with `$ ` start a command."""
    out, i = [], 0
    while i < len(body):
        raw = body[i]
        if prompt and not raw.startswith("$ "):
            i += 1
            continue
        start = i
        parts = []
        while True:
            part = strip_comment(body[i][2:] if (prompt and i == start) else body[i])
            cont = part.endswith("\\")
            parts.append(part[:-1] if cont else part)
            if not cont or i + 1 >= len(body):
                break
            i += 1
        text = " ".join(p.strip() for p in parts).strip()
        if text:
            out.append((first_line + start, body[start : i + 1], text, i))
        i += 1
    return out


def has_placeholder(text):
    if "..." in text or ".." in re.sub(r"\.\.?/", "", text) or re.search(r"(^|\s)\[", text):
        return True
    for tok in re.split(r"[\s=,:/|\"'()]+", text):
        if PLACEHOLDER_WORD.match(tok):
            return True
    return False


def classify(doc_lines):
    """Blocks with their commands classified; command blocks only matter."""
    blocks = parse_blocks(doc_lines)
    prev = None
    for b in blocks:
        first = next((line for line in b.body if line.strip()), "")
        plain = b.info in ("", "text")
        if b.info in ("sh", "bash", "shell"):
            cmds = logical_commands(b.body, b.start + 2, prompt=False)
        elif plain and first.startswith("$ "):
            b.transcript = True
            cmds = logical_commands(b.body, b.start + 2, prompt=True)
        elif plain and first.startswith("deploywatch "):
            # A usage synopsis: indented lines continue the command above.
            joined = [strip_comment(line) for line in b.body]
            joined = [
                line + (" \\" if n + 1 < len(joined) and joined[n + 1][:1].isspace() and not line.endswith("\\") else "")
                for n, line in enumerate(joined)
            ]
            cmds = logical_commands(joined, b.start + 2, prompt=False)
        else:
            cmds = []
            gap = doc_lines[prev.end + 1 : b.start] if prev else None
            if plain and prev is not None and prev.commands and not prev.transcript and all(
                not g.strip() for g in gap
            ):
                b.output_of = prev
        for n, (line, shown, text, last) in enumerate(cmds):
            text = CARGO_RUN.sub("deploywatch", text)
            c = Command(line=line, shown=shown, text=text)
            if b.transcript:
                nxt = cmds[n + 1][0] - (b.start + 2) if n + 1 < len(cmds) else len(b.body)
                c.output_lines = (last + 1, nxt)
            opted_in = False
            for what, prefix, reason in b.markers:
                if prefix is None or c.text.startswith(prefix):
                    if what == "skip":
                        c.kind, c.reason = "skip", reason
                    else:
                        opted_in, c.reason = True, reason
            if c.kind == "run" and has_placeholder(c.text):
                c.kind = "synopsis"
            elif c.kind == "run" and not (INVOCATION.search(c.text) or c.text.startswith("mkdir ") or opted_in):
                c.kind = "ref"
            b.commands.append(c)
        prev = b
    return blocks


def lint(path, blocks):
    """A command block the checker would not see is an error: label it `sh`."""
    out = []
    for b in blocks:
        first = next((line for line in b.body if line.strip()), "")
        if b.info in ("", "text") and not b.commands and not b.output_of and first.startswith(COMMAND_WORDS):
            out.append(
                Failure(path, b.start + 1, first.strip(), "a command in a block not labelled `sh`: label it ```sh")
            )
    return out


# ------------------------------------------------------------ the checks


class Checker:
    def __init__(self, binary):
        self.binary = binary
        self.helps = {}
        self.list_only = False
        self.packages = set()
        for manifest in glob.glob(str(ROOT / "*/Cargo.toml")) + [str(ROOT / "Cargo.toml")]:
            text = Path(manifest).read_text()
            self.packages.update(re.findall(r'^\[package\][^\[]*?^name\s*=\s*"([^"]+)"', text, re.M | re.S))

    def help_of(self, sub):
        if sub not in self.helps:
            r = subprocess.run([self.binary, sub, "--help"], capture_output=True, text=True)
            self.helps[sub] = r.stdout if r.returncode == 0 else None
        return self.helps[sub]

    def synopsis_errors(self, text):
        """Each `deploywatch SUB` exists and each of its flags is in its --help."""
        errors = []
        matches = list(INVOCATION.finditer(text))
        for n, m in enumerate(matches):
            sub = m.group(1)
            end = matches[n + 1].start() if n + 1 < len(matches) else len(text)
            args = re.split(r";|&&", text[m.end() : end])[0]
            help_text = self.help_of(sub)
            if help_text is None:
                errors.append(f"`deploywatch {sub}` is no subcommand (`deploywatch {sub} --help` fails)")
                continue
            for tok in args.split():
                for alt in tok.strip("[]()").split("|"):
                    fm = re.match(r"^\[?(--?[A-Za-z][\w-]*)", alt)
                    if fm and not re.search(r"(?<![\w-])" + re.escape(fm.group(1)) + r"(?![\w-])", help_text):
                        errors.append(f"`deploywatch {sub}` has no option {fm.group(1)} (not in its --help)")
        return errors

    def reference_errors(self, text):
        """Repository paths, cargo targets and packages a command names exist."""
        errors = []
        try:
            toks = shlex.split(text)
        except ValueError:
            toks = text.split()
        for n, tok in enumerate(toks):
            if tok.startswith(REPO_DIRS) and "$" not in tok and "/target/" not in tok and not has_placeholder(tok):
                if not glob.glob(str(ROOT / tok)):
                    errors.append(f"{tok}: no such file in the repository")
            nxt = toks[n + 1] if n + 1 < len(toks) else ""
            kinds = {"--test": "tests", "--bench": "benches", "--example": "examples"}
            if tok in kinds and not (
                glob.glob(str(ROOT / "**" / kinds[tok] / f"{nxt}.rs"), recursive=True)
                or glob.glob(str(ROOT / "**" / kinds[tok] / nxt / "main.rs"), recursive=True)
            ):
                errors.append(f"{tok} {nxt}: no {kinds[tok]}/{nxt}.rs or {kinds[tok]}/{nxt}/main.rs in the repository")
            if tok == "-p" and nxt not in self.packages:
                errors.append(f"-p {nxt}: no such package")
        return errors

    def run(self, cmd, workdir, bindir):
        env = dict(
            os.environ,
            PATH=f"{bindir}{os.pathsep}{os.environ['PATH']}",
            # scripts that would otherwise build a release binary use this one
            DEPLOYWATCH=str(Path(bindir) / "deploywatch"),
        )
        t0 = time.monotonic()
        try:
            r = subprocess.run(
                ["bash", "-e", "-o", "pipefail", "-c", cmd.text],
                cwd=workdir,
                env=env,
                capture_output=True,
                text=True,
                timeout=COMMAND_TIMEOUT_S,
            )
        except subprocess.TimeoutExpired:
            return None, f"timed out after {COMMAND_TIMEOUT_S} s", time.monotonic() - t0
        if r.returncode != 0:
            tail = "\n".join(r.stderr.rstrip().splitlines()[-15:])
            return None, f"exit {r.returncode}; stderr:\n{tail}", time.monotonic() - t0
        cmd.stdout = r.stdout
        return r.stdout, None, time.monotonic() - t0


def mask(text):
    lines = [line.rstrip() for line in text.splitlines()]
    while lines and not lines[-1]:
        lines.pop()
    out = "\n".join(lines)
    for regex, replacement, _why in MASKS:
        out = regex.sub(replacement, out)
    return out


def diff(shown, today):
    return "\n".join(
        difflib.unified_diff(mask(shown).splitlines(), mask(today).splitlines(), "shown", "today", lineterm="")
    )


def workspace():
    """A temporary directory that links every top-level entry of the repository."""
    tmp = Path(tempfile.mkdtemp(prefix="doc-examples-"))
    for entry in ROOT.iterdir():
        if entry.name not in ("out", ".git"):
            (tmp / entry.name).symlink_to(entry)
    return tmp


def check_doc(checker, path, update, report):
    """Runs one doc; returns its failures (and rewrites it with `update`)."""
    rel = os.path.relpath(path, ROOT) if str(path).startswith(str(ROOT)) else str(path)
    lines = Path(path).read_text().splitlines()
    blocks = classify(lines)
    failures = lint(rel, blocks)
    edits = []  # (first, last_exclusive, new lines), 0-based, on `lines`
    tmp = workspace()
    bindir = tmp / ".doc-examples-bin"
    bindir.mkdir()
    (bindir / "deploywatch").symlink_to(checker.binary)
    try:
        for b in blocks:
            for c in b.commands:
                label = c.text if len(c.text) <= 100 else c.text[:97] + "..."
                if c.kind != "run":
                    errs = checker.synopsis_errors(c.text) + checker.reference_errors(c.text)
                    failures += [Failure(rel, c.line, c.text, e) for e in errs]
                    why = f" ({c.reason})" if c.reason else ""
                    report.append((c.kind, rel, c.line, label + why, 0.0))
                    continue
                if checker.list_only:
                    report.append(("run", rel, c.line, label, 0.0))
                    continue
                stdout, err, secs = checker.run(c, tmp, bindir)
                report.append(("run", rel, c.line, label, secs))
                if err:
                    failures.append(Failure(rel, c.line, c.text, err))
                    continue
                if b.transcript:
                    first, last = c.output_lines
                    shown = "\n".join(b.body[first:last])
                    if mask(shown) != mask(stdout):
                        if update:
                            edits.append((b.start + 1 + first, b.start + 1 + last, stdout.rstrip("\n").splitlines()))
                        else:
                            failures.append(Failure(rel, c.line, c.text, diff(shown, stdout)))
        for b in blocks:
            src = b.output_of
            if src is None or not any(c.kind == "run" for c in src.commands):
                continue
            if any(c.kind == "run" and c.stdout is None for c in src.commands):
                continue
            today = "".join(c.stdout for c in src.commands if c.kind == "run")
            shown = "\n".join(b.body)
            if mask(shown) != mask(today):
                if update:
                    edits.append((b.start + 1, b.end, today.rstrip("\n").splitlines()))
                else:
                    cmd = " ; ".join(c.text for c in src.commands if c.kind == "run")
                    failures.append(Failure(rel, b.start + 1, cmd, diff(shown, today)))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if update and edits:
        for first, last, new in sorted(edits, reverse=True):
            lines[first:last] = new
        Path(path).write_text("\n".join(lines) + "\n")
        print(f"updated {len(edits)} output(s) in {rel}")
    return failures


def build():
    """The test build's `deploywatch` (scripts/deploywatch-bin.py builds what is missing)."""
    out = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "deploywatch-bin.py")],
        cwd=ROOT,
        check=True,
        stdout=subprocess.PIPE,
        text=True,
    ).stdout
    return Path(out.strip())


def run_docs(checker, paths, update):
    report, failures = [], []
    t0 = time.monotonic()
    for p in paths:
        failures += check_doc(checker, p, update, report)
    for kind, rel, line, label, secs in report:
        timing = f"{secs:6.1f} s" if kind == "run" else " " * 8
        print(f"{kind:8} {timing}  {rel}:{line}: {label}")
    counts = {k: sum(1 for r in report if r[0] == k) for k in ("run", "synopsis", "skip", "ref")}
    print(
        f"{counts['run']} run, {counts['synopsis']} synopsis, {counts['skip']} skipped, "
        f"{counts['ref']} references (not run); "
        f"{time.monotonic() - t0:.0f} s"
    )
    for f in failures:
        print(f"\nFAIL {fail_text(f)}", file=sys.stderr)
    return failures


# -------------------------------------------------------------- self-test

SELF_TEST_DOC = """# A doc

```sh
deploywatch margin --mechanism data/mechanisms/seed000_case1.toml --friction 0.54,0.472 -q
```

```
{output}
```

```sh
deploywatch margin --mechanism M.toml {flag} X
```
"""


def self_test(checker):
    """The checker on small docs of its own: it must fail where they are wrong."""
    tmp = Path(tempfile.mkdtemp(prefix="doc-examples-self-test-"))
    problems = []
    try:
        doc = tmp / "doc.md"
        # 1. A wrong output fails, naming the file, the line of the output and a diff.
        doc.write_text(SELF_TEST_DOC.format(output="not what margin prints", flag="--friction"))
        f = check_doc(checker, doc, False, [])
        if not (len(f) == 1 and f[0].line == 7 and "+" in f[0].message and "margin" in f[0].command):
            problems.append(f"a wrong output: expected one failure at line 7 with a diff, got {f}")
        # 2. --update writes today's output, after which the doc passes.
        check_doc(checker, doc, True, [])
        f = check_doc(checker, doc, False, [])
        if f or "not what margin prints" in doc.read_text():
            problems.append(f"after --update the doc should pass, got {f}")
        # 3. A changed number in the output fails (masks are narrow).
        text = doc.read_text()
        changed = re.sub(r"\d", lambda m: str((int(m.group()) + 1) % 10), text.split("```")[3], count=1)
        parts = text.split("```")
        parts[3] = changed
        doc.write_text("```".join(parts))
        if not check_doc(checker, doc, False, []):
            problems.append("a changed digit in the output should fail")
        # 4. A synopsis with an option the subcommand does not have fails.
        doc.write_text(
            "```sh\ndeploywatch margin --mechanism M.toml --no-such-option X\n"
            "deploywatch no-such-command RUN.csv\n```\n"
        )
        f = check_doc(checker, doc, False, [])
        msgs = " ".join(x.message for x in f)
        if "--no-such-option" not in msgs or "no-such-command" not in msgs:
            problems.append(f"a synopsis with an unknown option and subcommand should fail twice, got {f}")
        # 5. A command that exits non-zero fails; a skipped one is not run.
        doc.write_text(
            "```sh\ndeploywatch margin --mechanism data/mechanisms/no_such.toml --friction 1\n```\n\n"
            "<!-- doc-examples: skip (self-test) -->\n```sh\nfalse\nscripts/no-such-script.sh\n```\n"
        )
        f = check_doc(checker, doc, False, [])
        msgs = " ".join(x.message for x in f)
        if "exit 2" not in msgs or "scripts/no-such-script.sh" not in msgs or len(f) != 2:
            problems.append(f"a failing run and a missing script should fail, got {f}")
        # 6. A transcript (`$ ` lines and their output) is compared and updated alike.
        transcript = (
            "```text\n$ deploywatch margin --mechanism data/mechanisms/seed000_case1.toml \\\n"
            "      --friction 0.54,0.472 -q\nnot what margin prints\n```\n"
        )
        doc.write_text(transcript)
        f = check_doc(checker, doc, False, [])
        check_doc(checker, doc, True, [])
        g = check_doc(checker, doc, False, [])
        if len(f) != 1 or f[0].line != 2 or g or "--friction 0.54,0.472 -q\n" not in doc.read_text():
            problems.append(f"a wrong transcript should fail at line 2 and pass after --update, got {f} then {g}")
        # 7. A command in an unlabelled block is flagged.
        doc.write_text("```\ncargo test -p deploywatch-tests --test structure\n```\n")
        if not check_doc(checker, doc, False, []):
            problems.append("a command in an unlabelled block should fail")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for p in problems:
        print(f"self-test FAILED: {p}", file=sys.stderr)
    if not problems:
        print("self-test passed: wrong output or transcript, changed digit, unknown option and subcommand, "
              "failing run, missing script and unlabelled command all fail; --update repairs the outputs")
    return not problems


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true", help="compare (the default)")
    mode.add_argument("--update", action="store_true", help="rewrite the shown outputs from today's run")
    mode.add_argument("--self-test", action="store_true", help="run the checker on docs of its own")
    mode.add_argument("--list", action="store_true", help="classify the commands and check synopses; run nothing")
    ap.add_argument("files", nargs="*", help="Markdown files (default: README.md and docs/*.md)")
    args = ap.parse_args()
    checker = Checker(build())
    checker.list_only = args.list
    if args.self_test:
        sys.exit(0 if self_test(checker) else 1)
    paths = [Path(f).resolve() for f in args.files] or [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
    failures = run_docs(checker, paths, args.update)
    if failures:
        print(f"\n{len(failures)} doc example(s) out of date; `python3 scripts/doc-examples.py --update` "
              "rewrites shown outputs", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
