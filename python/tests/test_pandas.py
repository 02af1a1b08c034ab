"""The pandas views of the results (`to_pandas()`): the same numbers as the
numpy arrays, under the run CSV's column names, indexed by time.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_pandas.py -q
"""

import numpy as np

import deploywatch as dw

T01 = "data/mechanisms/seed001_T01.toml"
RUN = "data/examples/a_seed001_eft/seed001_T01.csv"


def test_a_trajectory_as_a_dataframe(root, monkeypatch):
    monkeypatch.chdir(root)
    t = dw.simulate(T01, ["coulomb_friction:joint=1:value=0.5"])
    df = t.to_pandas()
    assert df.index.name == "t_s" and len(df) == len(t.t_s)
    np.testing.assert_array_equal(df.index.to_numpy(), t.t_s)
    for j in range(t.joints):
        np.testing.assert_array_equal(df[f"phi{j + 1}_deg"].to_numpy(), t.phi_deg[:, j])
        np.testing.assert_array_equal(df[f"rate{j + 1}_deg_s"].to_numpy(), t.rate_deg_s[:, j])


def test_a_replay_and_the_margins_as_dataframes(root, monkeypatch):
    monkeypatch.chdir(root)
    r = dw.replay(RUN, T01)
    df = r.to_pandas()
    np.testing.assert_array_equal(df.index.to_numpy(), r.columns["t_s"])
    for name, col in r.columns.items():
        if name != "t_s":
            np.testing.assert_array_equal(df[name].to_numpy(), col)
    for name, texts in r.states.items():
        assert tuple(df[name]) == texts
    m = dw.margin(T01)
    mf = m.to_pandas()
    assert len(mf) == 3
    for name, col in m.joints.items():
        np.testing.assert_array_equal(mf[name].to_numpy(), col)


def test_a_dataframe_of_parameters_is_taken_by_its_column_names(root, monkeypatch):
    """A frame whose columns are the parameters' labels runs the same
    deployments in any column order; columns named otherwise are refused,
    named; columns numbered 0, 1, ... are taken by position."""
    import pandas as pd
    import pytest

    monkeypatch.chdir(root)
    vary = ["coulomb_friction:joint=1:lognormal(2.63,0.05)", "coulomb_friction:joint=2:lognormal(1.7,0.05)"]
    labels = dw.parameters(T01, vary)
    rows = np.array([[2.63, 1.70], [2.63, 1.90], [2.40, 1.80]])
    want = dw.simulate_batch(T01, vary, rows)
    df = pd.DataFrame(rows, columns=labels)
    for frame in (df, df[[labels[1], labels[0]]], pd.DataFrame(rows)):
        got = dw.simulate_batch(T01, vary, frame)
        np.testing.assert_array_equal(got.g, want.g)
    assert not np.array_equal(dw.simulate_batch(T01, vary, rows[:, ::-1]).g, want.g), "the columns matter"
    import re

    with pytest.raises(dw.InputError, match=r"unknown: friction1, missing: " + re.escape(labels[0])):
        dw.simulate_batch(T01, vary, df.rename(columns={labels[0]: "friction1"}))
    masked = np.ma.masked_array(rows, mask=[[False, False], [False, True], [False, False]])
    with pytest.raises(dw.InputError, match=r"params\[1, 1\]: masked"):
        dw.simulate_batch(T01, vary, masked)


def test_an_effect_given_two_laws_is_two_named_columns(root, monkeypatch):
    """Two sources of one joint's friction: two parameters whose draws add,
    each with its own name (the second `#2`), in `parameters()` and in the
    most likely failure's parameters (none lost to a key given twice)."""
    monkeypatch.chdir(root)
    law = "coulomb_friction:joint=1:normal(0.98,0.1)"
    mech = "data/mechanisms/reliability_two_modes.toml"
    labels = dw.parameters(mech, [law, law])
    assert labels == [law, "coulomb_friction:joint=1#2:normal(0.98,0.1)"], labels
    r = dw.reliability(mech, vary=[law, law], method="mc", samples=200, seed=1)
    point = r.most_likely_failure
    assert point is not None and len(point.parameters) == len(point.u) == 2, point
