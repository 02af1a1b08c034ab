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
