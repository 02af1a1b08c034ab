"""A process forked after the parent ran a batch runs its own batches: the
host's parallel loops use rayon's global pool, whose threads a fork does
not copy, so a forked child (multiprocessing's default on Linux, a
`ProcessPoolExecutor()` in a notebook) gets a pool of its own instead of
waiting for ever. The child's results equal the parent's.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_fork.py -q
"""

import multiprocessing as mp
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import deploywatch as dw

MECH = "data/mechanisms/seed001_T01.toml"
VARY = ["coulomb_friction:joint=1:lognormal(0.5,0.5)"]
ROWS = [[0.5], [0.6], [0.7], [0.8]]
# A batch of four T01 deployments takes well under a second; a child that
# waits for threads that do not exist never answers.
TIMEOUT_S = 120


def batch_g(_):
    return dw.simulate_batch(MECH, VARY, ROWS).g.tolist()


def reliability_dict(**kw):
    return dw.reliability(MECH, **kw).to_dict()


pytestmark = pytest.mark.skipif(
    sys.platform != "linux", reason="the fork start method is Linux's default"
)


def test_a_child_forked_after_a_batch_runs_its_own():
    here = dw.simulate_batch(MECH, VARY, ROWS).g.tolist()
    with mp.get_context("fork").Pool(1) as pool:
        there = pool.map_async(batch_g, [0]).get(timeout=TIMEOUT_S)[0]
    assert np.array_equal(np.array(here), np.array(there))


def test_a_fork_pool_executor_after_reliability_answers():
    kw = dict(vary=VARY, fail=["not_latched"], method="mc", samples=20, seed=3)
    here = reliability_dict(**kw)
    with ProcessPoolExecutor(1, mp_context=mp.get_context("fork")) as ex:
        there = ex.submit(reliability_dict, **kw).result(timeout=TIMEOUT_S)
    assert there == here
