"""A small program that uses deploywatch through its types: `mypy --strict`
must pass on it against the installed package (its `py.typed` and stubs),
and it runs (scripts/test.sh, python step):

    cd python/tests/typed && ../../../.venv/bin/mypy --strict usage.py
    .venv/bin/python python/tests/typed/usage.py
"""

from __future__ import annotations

import pathlib
from concurrent.futures import ThreadPoolExecutor
from typing import List, Optional

import numpy as np

import deploywatch
from deploywatch import (
    Batch,
    DesignPoint,
    Estimate,
    FloatArray,
    ModeResult,
    Reliability,
    Trajectory,
)

ROOT = pathlib.Path(__file__).resolve().parents[3]
MECH = ROOT / "data/mechanisms/reliability_one_panel.toml"
VARY = ["coulomb_friction:joint=1:normal(1.1,0.1)"]


def latch_instants() -> FloatArray:
    run: Trajectory = deploywatch.simulate(MECH, ["coulomb_friction:joint=1:value=1.2"])
    return run.latch_s


def failed_rows() -> List[int]:
    batch: Batch = deploywatch.simulate_batch(MECH, VARY, np.array([[1.0], [1.6]]))
    margins: FloatArray = batch.margins
    assert margins.shape == (2, 1)
    return [int(i) for i in np.flatnonzero(batch.failed)]


def probability(executor: Optional[ThreadPoolExecutor] = None) -> float:
    r: Reliability = deploywatch.reliability(
        MECH, vary=VARY, fail=["not_latched"], method="subset", samples=1000, seed=1,
        executor=executor,
    )
    point = r.most_likely_failure
    beta: float = point.beta if point is not None else float("inf")
    modes: tuple[ModeResult, ...] = r.modes
    assert beta > 0 and all(level.p > 0 for m in modes for level in m.levels)
    return r.p_fail


def checked(executor: Optional[ThreadPoolExecutor] = None) -> Optional[bool]:
    r: Reliability = deploywatch.reliability(
        MECH, vary=VARY, fail=["not_latched"], samples=500, seed=1, executor=executor
    )
    subset: Optional[Estimate] = r.estimates.get("subset")
    points: tuple[DesignPoint, ...] = r.estimates["is"].design_points
    assert r.method == "auto" and subset is not None and len(points) == 1
    return r.agree


def typed_model() -> float:
    m: deploywatch.Mechanism = deploywatch.Mechanism.from_toml(MECH)
    panel: deploywatch.Panel = m.panels[0]
    latch: Optional[deploywatch.Latch] = m.latches[0]
    effects: List[deploywatch.EffectLike] = [deploywatch.Coulomb(joint=1, torque_nm=0.5), "viscous_damping:joint=1:value=0.01"]
    run: Trajectory = m.simulate(effects=effects)
    vary = [deploywatch.Vary("coulomb_friction", 1, deploywatch.Normal(1.1, 0.1))]
    r = deploywatch.reliability(m, vary=vary, fail=[deploywatch.NotLatched()], method="mc", samples=50)
    margins: deploywatch.Margins = deploywatch.margin(m)
    torque: FloatArray = margins.joints["torque_margin_pct"]
    monitor = deploywatch.Monitor(m)
    status: deploywatch.MonitorStatus = monitor.update(deploywatch.Sample(t_s=0.0, phi_deg=[m.joints[0].stowed_deg], latch=[False]))
    coulomb: FloatArray = status.coulomb_nm
    assert latch is None and panel.mass_kg > 0 and r.p_fail >= 0 and torque.shape == (1,) and coulomb.shape == (1,)
    return float(run.end_s)


def main() -> None:
    typed_model()
    try:
        deploywatch.simulate_batch(MECH, VARY, np.zeros((1, 2)))
    except deploywatch.InputError as e:
        message: str = e.message
        causes: tuple[str, ...] = e.causes
        assert message.startswith("params:") and causes == ()
    with ThreadPoolExecutor(max_workers=2) as ex:
        assert probability(ex) == probability()
        assert checked(ex) == checked()
    print(deploywatch.__version__, latch_instants(), failed_rows())


if __name__ == "__main__":
    main()
