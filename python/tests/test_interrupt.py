"""Ctrl-C stops a long `reliability()` (KeyboardInterrupt between two
batches) instead of being seen only when the run ends: a crude Monte-Carlo
of 10⁹ deployments (days of work) in a child process that sends itself
SIGINT one second in. The child must end with KeyboardInterrupt; the
timeout only bounds a run that ignores the signal.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_interrupt.py -q
"""

import subprocess
import sys

import pytest

CHILD = """
import os, signal, sys, threading, time
from concurrent.futures import ThreadPoolExecutor
import deploywatch

def interrupt():
    time.sleep(1.0)
    os.kill(os.getpid(), signal.SIGINT)

executor = ThreadPoolExecutor(max_workers=2) if sys.argv[1] == "threads" else None
threading.Thread(target=interrupt, daemon=True).start()
try:
    deploywatch.reliability(
        "data/mechanisms/reliability_one_panel.toml",
        vary=["coulomb_friction:joint=1:normal(1.1,0.1)"],
        method="mc", samples=10**9, seed=0, executor=executor, chunk=500,
    )
except KeyboardInterrupt:
    print("KeyboardInterrupt")
    sys.exit(0)
print("ran to the end")
sys.exit(1)
"""


@pytest.mark.parametrize("where", ["local", "threads"])
def test_ctrl_c_stops_a_long_reliability(root, where):
    try:
        done = subprocess.run(
            [sys.executable, "-c", CHILD, where],
            cwd=root, capture_output=True, text=True, timeout=120,
        )
    except subprocess.TimeoutExpired:
        pytest.fail("reliability() ignored SIGINT: still running after 120 s")
    assert done.stdout.strip() == "KeyboardInterrupt", done.stderr
    assert done.returncode == 0
