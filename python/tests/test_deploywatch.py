"""The Python package against the CLI: one deployment, a batch, and the
reliability analysis locally, on a thread pool and on a real Dask
LocalCluster of two worker processes, equal to the CLI's JSON bit for bit
(the typed result's `to_dict()` is the CLI's JSON object, and the CLI's
JSON read by `Reliability.from_dict` equals the typed result).

    bash scripts/python-env.sh && .venv/bin/pytest python/tests -q
"""

import json
import re
import subprocess
import warnings
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
    assert isinstance(r, deploywatch.Trajectory) and r.joints == 1
    n = r.t_s.shape[0]
    assert r.phi_deg.shape == (n, 1) and r.rate_deg_s.shape == (n, 1)
    assert r.t_s.dtype == np.float64 and r.phi_deg.dtype == np.float64
    assert r.phi_deg[0, 0] == 90.0
    assert r.latch_s[0] == pytest.approx(cli_latch_s(cli, root, tmp_path, effects), abs=1e-6)
    assert isinstance(r.end_s, float) and 0 < r.end_s <= r.t_s[-1]


@pytest.mark.parametrize(
    "mech, deployed",
    [
        (MECH, True),  # the chain of ideal latches
        ("data/mechanisms/seed000_case2_truss.toml", True),  # the truss wing
        ("data/mechanisms/seed001_T01_rig.toml", True),  # on the rig
        ("data/mechanisms/one_panel_pawl.toml", True),  # a physical latch
        ("data/mechanisms/one_panel_physical_latch.toml", False),  # one that does not latch
    ],
)
def test_end_s_is_the_last_sample_whichever_simulator(root, mech, deployed):
    """``end_s`` is where the run ends, its last sample, whichever
    simulator ran it (the chain's and the truss's integration stops at the
    last latch and their samples go on ``settle_s`` longer, the others'
    run to their last sample); the last latch is ``last_latch_s``, NaN
    when a joint did not latch."""
    r = deploywatch.simulate(root / mech)
    assert isinstance(r.end_s, float) and r.end_s == r.t_s[-1]
    assert np.isfinite(r.latch_s).all() == deployed
    if deployed:
        assert r.last_latch_s == np.max(r.latch_s) and r.last_latch_s <= r.end_s
    else:
        assert np.isnan(r.last_latch_s)
    if mech == MECH:
        m = deploywatch.Mechanism.from_toml(root / mech)
        # Recorded settle_s past the sample at or after the last latch.
        assert r.end_s - r.last_latch_s >= m.settle_s


def test_simulate_batch_rows_are_deployments(cli, root, tmp_path):
    params = np.array([[1.0, 0.16], [1.2, 0.2], [1.6, 0.16]])
    b = deploywatch.simulate_batch(root / MECH, VARY, params, fail=FAIL)
    assert isinstance(b, deploywatch.Batch)
    assert b.g.shape == (3,)
    # One margin per failure mode (not_latched, time>4 at joint 1); g is
    # the smallest, the system fails when any mode does.
    assert b.margins.shape == (3, 2) and b.margins.dtype == np.float64
    assert np.array_equal(b.g, b.margins.min(axis=1))
    assert b.margins[2, 0] < 0 and b.margins[0, 0] > 0 and b.margins[0, 1] > 0
    for a in (b.latch_s, b.latch_rate_deg_s, b.end_deg):
        assert a.shape == (3, 1) and a.dtype == np.float64
    # Row 0 is the mechanism with that friction and its own inertia.
    want = cli_latch_s(cli, root, tmp_path, ["coulomb_friction:joint=1:value=1.0"])
    assert b.latch_s[0, 0] == pytest.approx(want, abs=1e-6)
    # Friction 1.6 N·m stops the panel short of the latch: failed, g < 0.
    assert np.isnan(b.latch_s[2, 0]) and b.g[2] < 0 and b.end_deg[2, 0] > 0
    # The rate before the latch is sampled only for a latch_rate criterion.
    assert b.g[0] > 0 and np.isnan(b.latch_rate_deg_s).all()
    rated = deploywatch.simulate_batch(root / MECH, VARY, params, fail=FAIL + ["latch_rate>1000"])
    assert rated.latch_rate_deg_s[0, 0] < 0 and np.isnan(rated.latch_rate_deg_s[2, 0])
    assert rated.margins.shape == (3, 3)
    assert rated.margins[0, 2] == pytest.approx(1000 + rated.latch_rate_deg_s[0, 0])
    assert b.failed.tolist() == [False, False, True]
    # Integers and a list of lists are numbers too: the same bits.
    same = deploywatch.simulate_batch(root / MECH, VARY, params.tolist(), fail=FAIL)
    assert np.array_equal(same.g, b.g)
    assert deploywatch.parameters(root / MECH, VARY, FAIL) == VARY


def test_not_held_is_not_latched_with_an_ideal_latch(root):
    # The typed criterion is its string; with an ideal latch a joint is held
    # from its latch on, so the margins are not_latched's to the bit.
    assert str(deploywatch.NotHeld()) == "not_held"
    params = np.array([[1.0, 0.16], [1.6, 0.16]])
    held = deploywatch.simulate_batch(root / MECH, VARY, params, fail=[deploywatch.NotHeld()])
    latched = deploywatch.simulate_batch(root / MECH, VARY, params, fail=["not_latched"])
    assert np.array_equal(held.margins, latched.margins)
    assert held.failed.tolist() == [False, True]


def test_a_switch_open_over_a_latch_that_holds_is_a_warning(root):
    # Seed 001 T01 with its pawls: the most likely failure seen of eight
    # draws fails not_latched with a pawl in its notch and its switch open
    # at the end; Python warns as the CLI does on stderr, and not_held
    # (which none of them fails) raises no warning.
    pawl = root / "data/mechanisms/seed001_T01_pawl.toml"
    vary = [f"coulomb_friction:joint={j}:normal(0,{sd})" for j, sd in ((1, 0.1315), (2, 0.085), (3, 0.00005))]
    with pytest.warns(UserWarning, match="held by its latch.*the criterion not_held counts") as said:
        r = deploywatch.reliability(pawl, vary=vary, fail=["not_latched"], method="mc", samples=8, seed=0)
    assert said[0].filename == __file__, "the warning points at the caller's line"
    assert r.failures > 0
    # The result carries the same words, as the CLI's JSON does.
    assert len(r.warnings) == 1 and "the criterion not_held counts" in r.warnings[0]
    assert r.to_dict()["warnings"] == list(r.warnings)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        held = deploywatch.reliability(pawl, vary=vary, fail=[deploywatch.NotHeld()], method="mc", samples=8, seed=0)
    assert held.failures == 0 and held.warnings == ()


@pytest.fixture(scope="module")
def local(root):
    return deploywatch.reliability(root / MECH, vary=VARY, fail=FAIL, samples=1000, seed=3)


def equals_the_cli(got, want):
    """The typed result is the CLI's JSON object, both ways."""
    assert isinstance(got, deploywatch.Reliability)
    assert got.to_dict() == want and got == deploywatch.Reliability.from_dict(want)
    assert json.dumps(got.to_dict()) == json.dumps(want)  # the same keys in the same order
    assert got.extra == {}


def test_auto_equals_the_cli(cli, root, tmp_path, local):
    want = cli_json(cli, root, tmp_path, "--samples", "1000", "--seed", "3")
    equals_the_cli(local, want)
    assert local.method == "auto" and set(local.estimates) == {"is", "subset"}
    assert local.agree is not None and 0 < local.p_fail < 1
    imp, sub = local.estimates["is"], local.estimates["subset"]
    assert isinstance(imp, deploywatch.Estimate) and imp.method == "is" and sub.method == "subset"
    assert [m.mode for m in sub.modes] == ["not_latched at joint 1", "time>4 at joint 1"]
    assert all(p.beta > 0 and list(p.parameters) == [
        "coulomb_friction:joint=1", "panel_inertia:joint=1"] for p in imp.design_points)
    assert local.simulations == imp.simulations + sub.simulations


def test_subset_equals_the_cli(cli, root, tmp_path):
    got = deploywatch.reliability(root / MECH, vary=VARY, fail=FAIL, method="subset", samples=1000, seed=3)
    equals_the_cli(got, cli_json(cli, root, tmp_path, "--method", "subset", "--samples", "1000", "--seed", "3"))
    assert 0 < got.p_fail < 1 and got.method == "subset" and got.estimates == {} and got.agree is None
    assert len(got.modes) == 2 and got.design_points == ()
    reached = [m for m in got.modes if m.converged]
    assert reached and all(m.levels[-1].threshold == 0.0 and m.stop == "reached" for m in reached)
    point = got.most_likely_failure
    assert point is not None and point.g <= 0 and list(point.parameters) == [
        "coulomb_friction:joint=1", "panel_inertia:joint=1"]


def test_is_and_mc_equal_the_cli(cli, root, tmp_path):
    got = deploywatch.reliability(root / MECH, vary=VARY, fail=FAIL, method="is", samples=1000, seed=3)
    equals_the_cli(got, cli_json(cli, root, tmp_path, "--method", "is", "--samples", "1000", "--seed", "3"))
    assert got.modes == () and len(got.design_points) + len(got.unreached) >= 1
    assert "design_points" in got.to_dict() and "modes" not in got.to_dict()
    mc = deploywatch.reliability(root / MECH, vary=VARY, fail=FAIL, method="mc", samples=3000, seed=3)
    equals_the_cli(mc, cli_json(cli, root, tmp_path, "--method", "mc", "--samples", "3000", "--seed", "3"))
    assert mc.modes == () and mc.design_points == () and mc.estimates == {}
    assert not {"modes", "design_points", "unreached", "estimates", "agree"} & set(mc.to_dict())


def test_correlation_equals_the_cli(cli, root, tmp_path, local):
    corr = deploywatch.reliability(
        root / MECH, vary=VARY, fail=FAIL, samples=1000, seed=3, corr=["1,2,-0.6"]
    )
    want = cli_json(cli, root, tmp_path, "--samples", "1000", "--seed", "3", "--corr", "1,2,-0.6")
    equals_the_cli(corr, want)
    assert corr.corr == ("1,2,-0.6",) and corr.p_fail != local.p_fail


def test_an_unknown_field_is_kept(local):
    d = local.to_dict()
    d["wall_s"] = 1.5
    assert deploywatch.Reliability.from_dict(d).to_dict() == d


def test_a_thread_pool_gives_the_same_bits(root, local):
    with ThreadPoolExecutor(max_workers=3) as ex:
        got = deploywatch.reliability(
            root / MECH, vary=VARY, fail=FAIL, samples=1000, seed=3, executor=ex, chunk=17
        )
    assert got == local


def test_a_dask_local_cluster_gives_the_same_bits(root, local, dask_client):
    assert len(dask_client.scheduler_info()["workers"]) == 2
    got = deploywatch.reliability(
        root / MECH, vary=VARY, fail=FAIL, samples=1000, seed=3, executor=dask_client
    )
    assert got == local


def test_the_flight_unit_on_a_dask_cluster_is_the_local_one(root, dask_client):
    vary, fail = ["coulomb_friction:joint=1:normal(0.05,0.01)"], ["time>4.2"]
    local = deploywatch.reliability(root / RIG, vary, fail, method="mc", samples=8, flight=True)
    got = deploywatch.reliability(root / RIG, vary, fail, method="mc", samples=8, flight=True, executor=dask_client)
    assert got == local and got.p_fail == 0.0


def test_from_findings_of_another_wing_are_a_user_warning(root, tmp_path):
    """``from_`` findings made on another wing are applied as they are,
    with the CLI's words as a ``UserWarning`` and in ``warnings``."""
    eft = tmp_path / "eft.json"
    eft.write_text(
        '{"method": "direct", "joints": [{"joint": 1, "coulomb_nm": 1.2, "ci95": [1.0, 1.4]}],'
        ' "after": {"rms_deg": 0.02, "runs": [{"run": "a.csv", "mechanism": "another-wing", "rms_deg": 0.02}]}}'
    )
    said = "from_: found on another-wing, not on reliability-one-panel: applied as it is"
    with pytest.warns(UserWarning) as caught:
        r = deploywatch.reliability(root / MECH, from_=eft, fail=["not_latched"], method="mc", samples=50)
    assert said in [str(w.message) for w in caught]
    assert said in r.warnings
    assert all(w.filename == __file__ for w in caught)


RIG = "data/mechanisms/seed001_T01_rig.toml"

ONE_PANEL = """name = "one-panel"

[[panel]]
length_m = 0.8
mass_kg = 3.0
com_m = 0.4
inertia_kgm2 = 0.16

[[joint]]
stowed_deg = 90.0
spring = { kind = "linear", preload_nm = 1.0, stiffness_nm_per_rad = 0.5, count = 1 }
friction = { coulomb_nm = 0.2 }

[run]
duration_s = 8.0
sample_hz = 100.0
"""


def test_the_flight_unit_is_the_clis(cli, root, tmp_path):
    """``reliability(..., flight=True)`` is ``reliability --flight``: the
    rig taken out, the CLI's JSON bit for bit, on a thread pool too. On the
    rig joint 1 latches after 4.2 s in every draw, in flight in none."""
    vary, fail = ["coulomb_friction:joint=1:normal(0.05,0.01)"], ["time>4.2"]
    out = tmp_path / "flight.json"
    args = [cli, "reliability", RIG, "--vary", vary[0], "--fail", fail[0], "--method", "mc", "--samples", "12"]
    subprocess.run(args + ["--flight", "--json", str(out), "-q"], cwd=root, check=True, capture_output=True)
    flight = deploywatch.reliability(root / RIG, vary, fail, method="mc", samples=12, flight=True)
    assert flight.to_dict() == json.loads(out.read_text())
    assert flight.p_fail == 0.0
    rig = deploywatch.reliability(root / RIG, vary, fail, method="mc", samples=12)
    assert rig.p_fail == 1.0
    with ThreadPoolExecutor(max_workers=2) as ex:
        pooled = deploywatch.reliability(
            root / RIG, vary, fail, method="mc", samples=12, flight=True, executor=ex, chunk=5
        )
    assert pooled == flight
    with pytest.raises(deploywatch.InputError, match="flight: expected True or False"):
        deploywatch.reliability(root / RIG, vary, fail, method="mc", samples=12, flight=1)


def test_the_flight_unit_draws_the_loss_the_runs_cannot_tell_from_the_air(cli, root, tmp_path):
    """A one-panel wing's runs with hinge damping hidden: the diagnosis names
    air drag and lists the hinge's quadratic damping beside it; the flight
    unit leaves the air drag out and draws the hinge's loss in its place,
    saying so, as ``reliability --flight`` does."""
    wing = tmp_path / "wing.toml"
    wing.write_text(ONE_PANEL)
    run, diag = tmp_path / "run.csv", tmp_path / "d.json"
    hidden = "quadratic_damping:joint=1:value=0.3"
    subprocess.run([cli, "simulate", str(wing), "--effect", hidden, "--seed", "4", "-o", str(run), "-q"],
                   check=True, capture_output=True)
    # The diagnosis reads the run without its comment lines (the truth).
    body = "\n".join(l for l in run.read_text().splitlines() if not l.startswith("# effects"))
    run.write_text(body + "\n")
    subprocess.run([cli, "diagnose", "--mechanism", str(wing), "--json", str(diag), str(run), "-q"],
                   check=True, capture_output=True)
    ground = deploywatch.parameters(wing, from_=diag)
    flown = deploywatch.parameters(wing, from_=diag, flight=True)
    hinge = [p for p in flown if p.startswith("quadratic_damping:joint=1:")]
    assert len(hinge) == 1 and not any(p.startswith("air_drag") for p in flown), flown
    if any(p.startswith("air_drag") for p in ground):
        with pytest.warns(UserWarning, match="drawn in place of air_drag"):
            deploywatch.reliability(wing, from_=diag, method="mc", samples=4, flight=True)
    else:
        assert hinge[0] in ground, ground
