"""The on-board monitor from Python: ``Monitor(mech).update(sample)``, the
core's ``Monitor`` (the ``f32`` code the firmware runs) configured as
``deploywatch replay`` configures it and fed one sample at a time; the same
statuses as ``replay --target host``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, Sequence, Tuple

import numpy as _np

from . import _native
from ._errors import InputError
from ._model import Mechanism
from ._results import FloatArray


@dataclass(frozen=True)
class Sample:
    """One sample as the monitor receives it: time [s], the encoder angle of
    each joint [deg] (NaN for a missing reading), each latch switch
    (``True`` closed)."""

    t_s: float
    phi_deg: Sequence[float]
    latch: Sequence[bool]


@dataclass(frozen=True)
class MonitorStatus:
    """The monitor's status after a sample: ``t_s`` [s], ``samples`` seen,
    per joint (numpy, NaN where the monitor has no value) the angle
    ``phi_deg`` [deg], the rate ``rate_deg_s`` [deg/s], the friction
    estimates ``coulomb_nm`` [N·m] and ``viscous_nms`` [N·m·s/rad], the
    margin of the remaining stroke ``margin_pct`` [%], the predicted time
    to latch ``time_to_latch_s`` [s]; ``latch``, ``prediction`` and
    ``resolution`` the states' names (``resolution``: ``Resolved``, or
    ``Unresolved`` where the readings change faster than 100 Hz resolves,
    docs/monitor.md §6.2); ``raw`` the core's status as a dict."""

    t_s: float
    samples: int
    phi_deg: FloatArray
    rate_deg_s: FloatArray
    coulomb_nm: FloatArray
    viscous_nms: FloatArray
    margin_pct: FloatArray
    time_to_latch_s: FloatArray
    latch: Tuple[str, ...]
    prediction: Tuple[str, ...]
    resolution: Tuple[str, ...]
    raw: Dict[str, Any]


def _column(joints: Sequence[Dict[str, Any]], key: str) -> FloatArray:
    return _np.array([_np.nan if j.get(key) is None else float(j[key]) for j in joints], dtype=_np.float64)


def _name(v: Any) -> str:
    """An enum's serde form (a name, or a one-key dict) as its name."""
    if isinstance(v, dict) and len(v) == 1:
        return str(next(iter(v)))
    return str(v)


class Monitor:
    """The on-board monitor of a mechanism (1 to 8 joints: what the core's
    predictor holds)."""

    def __init__(self, mechanism: Mechanism) -> None:
        if not isinstance(mechanism, Mechanism):
            raise InputError(
                f"mechanism: expected a deploywatch.Mechanism (Mechanism.from_toml(path)), got {type(mechanism).__name__}"
            )
        self._monitor = _native.Monitor(mechanism._model)

    @property
    def joints(self) -> int:
        """The joint count."""
        return self._monitor.joints

    def update(self, sample: Sample) -> MonitorStatus:
        """One sample in (``replay_step``, as ``replay``), the status
        out."""
        if not isinstance(sample, Sample):
            raise InputError(f"sample: expected a deploywatch.Sample(t_s, phi_deg, latch), got {type(sample).__name__}")
        phi = [float(x) for x in sample.phi_deg]
        if isinstance(sample.latch, (str, bytes)) or any(isinstance(x, (str, bytes)) for x in sample.latch):
            # bool("0") is True: a switch read from text would read closed.
            raise InputError(f"sample.latch: expected one bool per switch (True: closed), got {sample.latch!r}")
        latch = [bool(x) for x in sample.latch]
        raw = self._monitor.update(float(sample.t_s), phi, latch)
        joints = raw["joints"]
        return MonitorStatus(
            t_s=float(raw["t_s"]),
            samples=int(raw["samples"]),
            phi_deg=_column(joints, "phi_deg"),
            rate_deg_s=_column(joints, "rate_deg_s"),
            coulomb_nm=_column(joints, "coulomb_nm"),
            viscous_nms=_column(joints, "viscous_nms"),
            margin_pct=_column(joints, "margin_pct"),
            time_to_latch_s=_column(joints, "time_to_latch_s"),
            latch=tuple(_name(j.get("latch")) for j in joints),
            prediction=tuple(_name(j.get("prediction")) for j in joints),
            resolution=tuple(_name(j.get("resolution")) for j in joints),
            raw=raw,
        )


