"""The on-board monitor from Python: ``Monitor(mech).update(sample)``, the
core's ``Monitor`` (the ``f32`` code the firmware runs) configured as
``deploywatch replay`` configures it and fed one sample at a time; the same
statuses as ``replay --target host``."""

from __future__ import annotations

import math as _math
from collections.abc import Mapping as _Mapping
from dataclasses import dataclass
from typing import Any, Dict, List, Sequence, Tuple

import numpy as _np

from . import _native
from ._checks import _finite, _real
from ._errors import InputError
from ._model import Mechanism
from ._results import FloatArray


@dataclass(frozen=True)
class Sample:
    """One sample as the monitor receives it: time ``t_s`` [s] (finite),
    the encoder angle of each joint ``phi_deg`` [deg] (finite; NaN for a
    missing reading), each latch switch ``latch`` (a ``bool``, ``True``
    closed; numpy's too), one per angle. Checked where it is written (an
    ``InputError`` naming ``Sample.field``), and kept as a float and
    tuples; the joint count is checked against the monitor's by
    :meth:`Monitor.update`."""

    t_s: float
    phi_deg: Sequence[float]
    latch: Sequence[bool]

    def __post_init__(self) -> None:
        t_s = _finite("Sample.t_s", self.t_s, "a finite time [s]")
        phi = tuple(
            _angle(f"Sample.phi_deg[{i}]", v) for i, v in enumerate(_items("Sample.phi_deg", self.phi_deg, "numbers"))
        )
        latch = tuple(
            _switch(f"Sample.latch[{i}]", v) for i, v in enumerate(_items("Sample.latch", self.latch, "bools"))
        )
        if len(latch) != len(phi):
            raise InputError(
                f"Sample.latch: expected one switch per angle of phi_deg ({len(phi)}), got {len(latch)}"
            )
        object.__setattr__(self, "t_s", t_s)
        object.__setattr__(self, "phi_deg", phi)
        object.__setattr__(self, "latch", latch)


def _items(name: str, value: Any, what: str) -> List[Any]:
    """The items of a per-joint list (a list, tuple or numpy array; not a
    string, whose characters Python would iterate, nor a mapping)."""
    if isinstance(value, (str, bytes, _Mapping)) or not hasattr(value, "__iter__"):
        raise InputError(f"{name}: expected a list of {what}, one per joint, got {type(value).__name__} {value!r}")
    return list(value)


def _angle(name: str, value: Any) -> float:
    """An encoder's reading [deg]: finite, or NaN for a missing one."""
    v = _real(name, value)
    if _math.isinf(v):
        raise InputError(f"{name}: expected an angle [deg], finite or NaN for a missing reading, got {v}")
    return v


def _switch(name: str, value: Any) -> bool:
    """A latch switch: a bool (``bool("0")`` is True: a switch read from
    text would read closed)."""
    if not isinstance(value, (bool, _np.bool_)):
        raise InputError(
            f"{name}: expected one bool per switch (True: closed), got {type(value).__name__} {value!r}"
        )
    return bool(value)


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
        out. The sample's fields were checked when it was made; its joint
        count is checked here (``InputError``)."""
        if not isinstance(sample, Sample):
            raise InputError(f"sample: expected a deploywatch.Sample(t_s, phi_deg, latch), got {type(sample).__name__}")
        raw = self._monitor.update(sample.t_s, list(sample.phi_deg), list(sample.latch))
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


