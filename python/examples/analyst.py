"""From two measured runs to the diagnosis, the torque margins (on the
ground and along the stroke) and P(fail) on a Dask LocalCluster: a
notebook-style walk through the Python API (each ``# %%`` is a cell;
Jupyter, VS Code and Spyder run them one by one).

    .venv/bin/python python/examples/analyst.py OUT_DIR

It writes into OUT_DIR (which must exist) the diagnosis JSON, its Markdown
report and plots (the project's own PNGs), and prints what an analyst
reads off each step. python/tests/test_analyst.py runs it and compares what
it prints with docs/python.md section 4.
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
    latches = ["ideal" if latch is None else "physical" for latch in m.latches]
    print(f"{m.name}: {len(m.panels)} panels, {m.joints[0].spring} springs, latches {', '.join(latches)}")

# %% What the nominal model predicts
nominal = T01.simulate()
print("T01 nominal latch instants [s]:", np.round(nominal.latch_s, 3))

# %% The diagnosis: what the model gets wrong, and the named cause
diag = dw.diagnose(RUNS, [T01, T02], json=OUT / "diagnosis.json")
print(f"diagnosis: report {pathlib.Path(diag.report).name}, plots beside it")
found = diag.json["effects"]
for e in found:
    print(f"  {e['name']} at joint {e['joint']}: {e['value']:.3f} {e['unit']}")

# %% The model with the causes found: it now latches when the runs did
extended = T01.simulate(effects=[f"{e['name']}:joint={e['joint']}:value={e['value']}" for e in found])
print("T01 latch instants with them [s]:", np.round(extended.latch_s, 3))

# %% Torque margins with what was found (ECSS factors), and along the stroke
margins = dw.margin(T01, from_=OUT / "diagnosis.json", standard="ecss-e-st-33-01c")
for j, t in zip(margins.joints["joint"], margins.joints["torque_margin_pct"]):
    shown = f"{t:.0f} %" if np.isfinite(t) else "not finite (no resistance counted)"
    print(f"  T01 joint {int(j)}: torque margin {shown}")
status = dw.replay(RUNS[0], T01)
for j in range(1, len(T01.joints) + 1):
    col = status.columns.get(f"margin{j}_pct")
    if col is not None and np.isfinite(col).any():
        print(f"  T01 joint {j}: the monitor's margin of the remaining stroke, lowest {np.nanmin(col):.0f} %")

# %% The friction found, made uncertain: P(fail) on a Dask LocalCluster
# Two workers in this process (threads: the deployments release the GIL).
# Worker processes (`processes=True`) work as well from a notebook; a script
# needs an `if __name__ == "__main__":` guard for them, as their start
# imports the script again.
friction = [e for e in found if e["name"] == "coulomb_friction"]
vary = [dw.Vary("coulomb_friction", e["joint"], dw.LogNormal(e["value"], 0.5)) for e in friction]
fail = [dw.NotLatched()]
with LocalCluster(  # type: ignore[no-untyped-call]
    n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
) as cluster, Client(cluster) as client:  # type: ignore[no-untyped-call]
    r = dw.reliability(T01, vary=vary, fail=fail, method="subset", samples=500, seed=1, executor=client)
local = dw.reliability(T01, vary=vary, fail=fail, method="subset", samples=500, seed=1)
print(f"P(fail) = {r.p_fail:.3e} with {', '.join(str(v) for v in vary)}; equal to the local run: {r == local}")
