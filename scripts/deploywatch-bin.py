#!/usr/bin/env python3
"""Prints the path of the `deploywatch` binary of the workspace's test build,
building what is missing first.

    python3 scripts/deploywatch-bin.py

The docs' examples (scripts/doc-examples.py) and the firmware's replay
(scripts/firmware.sh) run this binary: the one `cargo test --workspace`
builds for the CLI tests (test profile: optimised, with debug assertions and
overflow checks). After `cargo test --workspace` nothing is compiled again,
so scripts/test.sh builds the workspace's dependencies once for the host
instead of again in release. The command is the test build's own
(`cargo test --workspace --no-run`, one test target named so that only the
library, the binary and that test are built when run alone); cargo prints
where it put the binary (`--message-format json`, the `executable` of the
`deploywatch` bin target).
"""

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# DEPLOYWATCH_BIN_AS_TESTS=1 (scripts/test.sh, after its cargo test): the
# selection of that whole test build (`--lib --bins --tests`), so that cargo
# finds everything fresh. Built alone with `--test replay`, cargo resolves
# the dependencies' features for fewer targets and compiled part of the
# workspace again (minutes of CI, in both lanes that ask for the binary).
SELECTION = (["--lib", "--bins", "--tests"] if os.environ.get("DEPLOYWATCH_BIN_AS_TESTS") == "1"
             else ["--test", "replay"])
COMMAND = [
    "cargo", "test", "--workspace", "--locked", "--no-run",
    *SELECTION, "--message-format", "json-render-diagnostics",
]


def path() -> Path:
    """Builds (if needed) and returns the path of the test build's binary."""
    out = subprocess.run(COMMAND, cwd=ROOT, check=True, stdout=subprocess.PIPE, text=True).stdout
    for line in out.splitlines():
        if not line.startswith("{"):
            continue
        msg = json.loads(line)
        target = msg.get("target") or {}
        if (msg.get("reason") == "compiler-artifact" and target.get("name") == "deploywatch"
                and "bin" in target.get("kind", ()) and msg.get("executable")
                # Not the bin's own unit-test harness (`--bins` builds both).
                and not (msg.get("profile") or {}).get("test")):
            return Path(msg["executable"])
    sys.exit("deploywatch-bin: `" + " ".join(COMMAND) + "` named no `deploywatch` binary")


if __name__ == "__main__":
    print(path())
