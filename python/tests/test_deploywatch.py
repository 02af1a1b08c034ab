"""The Python package against the CLI: one deployment, a batch, and the
reliability analysis locally, on a thread pool and on a real Dask
LocalCluster of two worker processes, equal to the CLI's JSON bit for bit.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests -q
"""

import json
import re
import subprocess
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import deploywatch

MECH = "data/mechanisms/reliability_one_panel.toml"
VARY = [
    "coulomb_friction:joint=1:normal(1.1,0.1)",
    "panel_inertia:joint=1:truncnormal(0.16,0.02,0.1,0.3)",
]
FAIL = ["not_latched", "time>4"]


def cli_latch_s(cli, root, tmp_path, effects):
    """The latch instant `deploywatch simulate` prints (6 decimals)."""
    args = [cli, "simulate", MECH, "--out", str(tmp_path / "run.csv"), "--no-noise", "-q"]
    for e in effects:
        args += ["--effect", e]
    out = subprocess.run(args, cwd=root, check=True, capture_output=True, text=True).stdout
    m = re.search(r"joint 1: latched at ([0-9.]+) s", out)
    return float(m.group(1)) if m else None


def cli_json(cli, root, tmp_path, *extra):
    out = tmp_path / "rel.json"
    args = [cli, "reliability", MECH, "--json", str(out), "-q"]
    for v in VARY:
        args += ["--vary", v]
    for f in FAIL:
        args += ["--fail", f]
    subprocess.run(args + list(extra), cwd=root, check=True, capture_output=True)
    return json.loads(out.read_text())


def test_simulate_matches_the_cli(cli, root, tmp_path):
    effects = ["coulomb_friction:joint=1:value=1.2"]
    r = deploywatch.simulate(root / MECH, effects)
    n = r["t_s"].shape[0]
    assert r["phi_deg"].shape == (n, 1) and r["rate_deg_s"].shape == (n, 1)
    assert r["phi_deg"][0, 0] == 90.0
    assert r["latch_s"][0] == pytest.approx(cli_latch_s(cli, root, tmp_path, effects), abs=1e-6)


def test_simulate_batch_rows_are_deployments(cli, root, tmp_path):
    params = np.array([[1.0, 0.16], [1.2, 0.2], [1.6, 0.16]])
    b = deploywatch.simulate_batch(root / MECH, VARY, params, fail=FAIL)
    assert b["g"].shape == (3,)
    for key in ("latch_s", "latch_rate_deg_s", "end_deg"):
        assert b[key].shape == (3, 1)
    # Row 0 is the mechanism with that friction and its own inertia.
    want = cli_latch_s(cli, root, tmp_path, ["coulomb_friction:joint=1:value=1.0"])
    assert b["latch_s"][0, 0] == pytest.approx(want, abs=1e-6)
    # Friction 1.6 N·m stops the panel short of the latch: failed, g < 0.
    assert np.isnan(b["latch_s"][2, 0]) and b["g"][2] < 0 and b["end_deg"][2, 0] > 0
    assert b["g"][0] > 0 and b["latch_rate_deg_s"][0, 0] < 0
    assert deploywatch.parameters(root / MECH, VARY, FAIL) == VARY


@pytest.fixture(scope="module")
def local(root):
    return deploywatch.reliability(root / MECH, vary=VARY, fail=FAIL, samples=1000, seed=3)


def test_reliability_equals_the_cli(cli, root, tmp_path, local):
    want = cli_json(cli, root, tmp_path, "--method", "auto", "--samples", "1000", "--seed", "3")
    assert local == want
    assert 0 < local["p_fail"] < 1 and local["converged"]
    mc = deploywatch.reliability(root / MECH, vary=VARY, fail=FAIL, method="mc", samples=3000, seed=3)
    assert mc == cli_json(cli, root, tmp_path, "--method", "mc", "--samples", "3000", "--seed", "3")
    corr = deploywatch.reliability(
        root / MECH, vary=VARY, fail=FAIL, samples=1000, seed=3, corr=["1,2,-0.6"]
    )
    assert corr == cli_json(cli, root, tmp_path, "--samples", "1000", "--seed", "3", "--corr", "1,2,-0.6")
    assert corr["corr"] == ["1,2,-0.6"] and corr["p_fail"] != local["p_fail"]


def test_a_thread_pool_gives_the_same_bits(root, local):
    with ThreadPoolExecutor(max_workers=3) as ex:
        got = deploywatch.reliability(
            root / MECH, vary=VARY, fail=FAIL, samples=1000, seed=3, executor=ex, chunk=17
        )
    assert got == local


def test_a_dask_local_cluster_gives_the_same_bits(root, local):
    from dask import distributed
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        got = deploywatch.reliability(
            root / MECH, vary=VARY, fail=FAIL, samples=1000, seed=3, executor=client
        )
    assert got == local
