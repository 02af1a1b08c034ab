"""From two measured runs to the diagnosis, the torque margins and P(fail)
on a Dask LocalCluster: a notebook-style walk through the Python API (each
``# %%`` is a cell; Jupyter, VS Code and Spyder run them one by one).

    .venv/bin/python python/examples/analyst.py OUT_DIR

It writes into OUT_DIR (which must exist): the diagnosis JSON, its
Markdown report and plots (the project's own PNGs), and prints what an
analyst reads off each step. python/tests/test_analyst.py runs it; its
output is shown in docs/python.md.
"""

# %% The two runs and their mechanisms, parsed once
import pathlib
import sys

import numpy as np
from dask.distributed import Client, LocalCluster

import deploywatch as dw

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(".")
RUNS = [ROOT / f"data/examples/c_seed001_friction_harness/seed001_{t}.csv" for t in ("T01", "T02")]
T01 = dw.Mechanism.from_toml(ROOT / "data/mechanisms/seed001_T01.toml")
T02 = dw.Mechanism.from_toml(ROOT / "data/mechanisms/seed001_T02.toml")
for m in (T01, T02):
    springs = ", ".join(j.spring for j in m.joints)
    print(f"{m.name}: {len(m.panels)} panels, springs {springs}, latches {['ideal' if l is None else 'physical' for l in m.latches]}")

# %% What the nominal model predicts
nominal = T02.simulate()
print("T02 nominal latch instants [s]:", np.round(nominal.latch_s, 3))

# %% The diagnosis: what the model gets wrong, the named cause
diag = dw.diagnose(RUNS, [T01, T02], json=OUT / "diagnosis.json")
print("diagnosis report:", pathlib.Path(diag.report).name)
for e in diag.json.get("effects", []):
    print("  found:", {k: e[k] for k in ("effect", "joint") if k in e})

# %% The equivalent friction of each joint, and the margins it leaves
eft = dw.identify(RUNS, [T01, T02], json=OUT / "eft.json")
margins = dw.margin(T02, from_=OUT / "eft.json", standard="ecss-e-st-33-01c")
for j, t, e in zip(margins.joints["joint"], margins.joints["torque_margin_pct"], margins.joints["energy_margin_pct"]):
    print(f"  T02 joint {int(j)}: torque margin {t:.0f} %, energy margin {e:.0f} %")

# %% The friction found, made uncertain: P(fail) on a Dask LocalCluster
vary = [dw.Vary("coulomb_friction", 2, dw.Normal(1.7, 0.3))]
with LocalCluster(  # type: ignore[no-untyped-call]
    n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
) as cluster, Client(cluster) as client:  # type: ignore[no-untyped-call]
    r = dw.reliability(
        T02, vary=vary, fail=[dw.NotLatched()], method="subset", samples=500, seed=1,
        from_=OUT / "eft.json", executor=client,
    )
local = dw.reliability(
    T02, vary=vary, fail=[dw.NotLatched()], method="subset", samples=500, seed=1, from_=OUT / "eft.json"
)
print(f"P(fail) = {r.p_fail:.3e} (c.o.v. {r.cov:.2f}); equal to the local run: {r == local}")
