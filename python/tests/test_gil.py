"""The long calls release the GIL: another Python thread runs while the
deployments are simulated. With the interpreter's switch interval made
huge, a thread gets the GIL only when the holder gives it up; a second
thread that stamps the clock every millisecond must leave a stamp strictly
between the instants before and after the call.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_gil.py -q
"""

import sys
import threading
import time

import numpy as np
import pytest

from deploywatch import _native

MECH = "data/mechanisms/reliability_one_panel.toml"
VARY = ["coulomb_friction:joint=1:normal(1.1,0.1)"]


def stamps_during(call):
    """The other thread's clock stamps that fall inside `call()`."""
    stamps, done = [], threading.Event()

    def ticker():
        while not done.is_set():
            stamps.append(time.monotonic())
            time.sleep(0.001)  # gives up the GIL

    old = sys.getswitchinterval()
    t = threading.Thread(target=ticker)
    t.start()
    time.sleep(0.01)
    sys.setswitchinterval(1000.0)
    try:
        t0 = time.monotonic()
        call()
        t1 = time.monotonic()
    finally:
        sys.setswitchinterval(old)
        done.set()
        t.join()
    return [s for s in stamps if t0 < s < t1]


@pytest.fixture(scope="module")
def text(root):
    return (root / MECH).read_text()


def test_simulate_batch_releases_the_gil(text):
    rows = np.full((2000, 1), 1.1)
    assert stamps_during(lambda: _native.simulate_batch(text, MECH, VARY, ["not_latched"], rows))


def test_reliability_releases_the_gil(text):
    call = lambda: _native.reliability(text, MECH, VARY, ["not_latched"], "mc", 2000, None, 0)  # noqa: E731
    assert stamps_during(call)
