"""The typed results of deploywatch: frozen dataclasses, numpy arrays for
the time series and batches, plain floats and tuples for the reliability
estimate (so that two estimates compare with ``==``, bit for bit)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Dict, Mapping, Optional, Tuple

import numpy as _np
import numpy.typing as _npt

FloatArray = _npt.NDArray[_np.float64]
"""A numpy array of float64."""


@dataclass(frozen=True, eq=False)
class Trajectory:
    """One simulated deployment (``deploywatch simulate``).

    ``t_s`` (n,) [s]; ``phi_deg`` and ``rate_deg_s`` (n, joints) [deg],
    [deg/s]; ``latch_s`` (joints,) [s], NaN where the joint did not latch;
    ``end_s`` where the simulation stopped [s].
    """

    t_s: FloatArray
    phi_deg: FloatArray
    rate_deg_s: FloatArray
    latch_s: FloatArray
    end_s: float

    @property
    def joints(self) -> int:
        """The number of joints."""
        return int(self.latch_s.shape[0])


@dataclass(frozen=True, eq=False)
class Batch:
    """A batch of deployments, one per row of ``params``
    (:func:`deploywatch.simulate_batch`).

    ``g`` (n,): the limit state, failure iff ``g <= 0``; ``latch_s`` [s] and
    ``latch_rate_deg_s`` [deg/s] (n, joints), NaN where not latched;
    ``end_deg`` (n, joints) [deg]: the angle at the end of the run.
    """

    g: FloatArray
    latch_s: FloatArray
    latch_rate_deg_s: FloatArray
    end_deg: FloatArray

    @property
    def failed(self) -> _npt.NDArray[_np.bool_]:
        """Which rows failed (``g <= 0``)."""
        return self.g <= 0.0


@dataclass(frozen=True)
class Level:
    """One level of subset simulation: its threshold ``b_k`` of ``g``
    (0 for the last), the conditional probability ``p``, its coefficient of
    variation ``cov``, and the deployments it took."""

    threshold: float
    p: float
    cov: float
    simulations: int


@dataclass(frozen=True)
class FailurePoint:
    """The failed draw of highest density: ``parameters`` (label -> value,
    in the units of each parameter), its standard normal point ``u``,
    ``beta = |u|`` and ``g`` there (<= 0)."""

    parameters: Mapping[str, float]
    u: Tuple[float, ...]
    beta: float
    g: float


@dataclass(frozen=True)
class Reliability:
    """The result of :func:`deploywatch.reliability`, field for field the
    JSON of ``deploywatch reliability --json`` (``to_dict()`` gives that
    JSON's dict back; ``from_dict`` reads it).

    ``p_fail`` the failure probability, ``cov`` its coefficient of
    variation, ``ci95`` its 95 % interval, ``simulations`` the deployments
    run, ``failures`` the failed ones (mc) or those of the last level
    (subset), ``converged``, ``most_likely_failure`` (None if none failed),
    ``levels`` (subset only; empty for mc). ``extra``: any field of the JSON
    this version does not know, kept as it came.
    """

    mechanism: str
    method: str
    seed: int
    vary: Tuple[str, ...]
    fail: Tuple[str, ...]
    corr: Tuple[str, ...]
    p_fail: float
    cov: float
    ci95: Tuple[float, float]
    simulations: int
    failures: int
    converged: bool
    most_likely_failure: Optional[FailurePoint]
    levels: Tuple[Level, ...] = ()
    extra: Mapping[str, Any] = field(default_factory=dict)

    _KNOWN = (
        "mechanism", "method", "seed", "vary", "fail", "corr", "p_fail", "cov",
        "ci95", "simulations", "failures", "converged", "most_likely_failure",
        "levels",
    )

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Reliability":
        """The result from the JSON object of ``deploywatch reliability
        --json`` (as ``json.load`` gives it) or from the extension."""
        point = d.get("most_likely_failure")
        lo, hi = d["ci95"]
        return cls(
            mechanism=str(d["mechanism"]),
            method=str(d["method"]),
            seed=int(d["seed"]),
            vary=tuple(d["vary"]),
            fail=tuple(d["fail"]),
            corr=tuple(d.get("corr", ())),
            p_fail=_num(d["p_fail"]),
            cov=_num(d["cov"], none=math.inf),
            ci95=(_num(lo), _num(hi)),
            simulations=int(d["simulations"]),
            failures=int(d["failures"]),
            converged=bool(d["converged"]),
            most_likely_failure=None if point is None else FailurePoint(
                parameters={str(k): float(v) for k, v in point["parameters"].items()},
                u=tuple(float(x) for x in point["u"]),
                beta=_num(point["beta"]),
                g=_num(point["g"]),
            ),
            levels=tuple(
                Level(_num(lv["threshold"]), _num(lv["p"]),
                      _num(lv["cov"], none=math.inf), int(lv["simulations"]))
                for lv in d.get("levels", ())
            ),
            extra={k: v for k, v in d.items() if k not in cls._KNOWN},
        )

    def to_dict(self) -> Dict[str, Any]:
        """The JSON object ``deploywatch reliability --json`` writes for the
        same analysis (the same keys in the same order, ``levels`` for
        subset only)."""
        point = self.most_likely_failure
        out: Dict[str, Any] = {
            "mechanism": self.mechanism,
            "method": self.method,
            "seed": self.seed,
            "vary": list(self.vary),
            "fail": list(self.fail),
            "corr": list(self.corr),
            "p_fail": _json(self.p_fail),
            "cov": _json(self.cov),
            "ci95": [_json(x) for x in self.ci95],
            "simulations": self.simulations,
            "failures": self.failures,
            "converged": self.converged,
            "most_likely_failure": None if point is None else {
                "parameters": dict(point.parameters),
                "u": list(point.u),
                "beta": _json(point.beta),
                "g": _json(point.g),
            },
        }
        if self.levels or self.method == "subset":
            out["levels"] = [
                {"threshold": _json(lv.threshold), "p": _json(lv.p), "cov": _json(lv.cov),
                 "simulations": lv.simulations}
                for lv in self.levels
            ]
        out.update(self.extra)
        return out


def _num(x: Any, none: float = math.nan) -> float:
    """A float of the JSON, where ``null`` stands for a value JSON cannot
    hold (serde_json writes infinities and NaN as ``null``): ``none``."""
    return none if x is None else float(x)


def _json(x: float) -> Optional[float]:
    """A float as serde_json writes it: ``None`` if not finite."""
    return x if math.isfinite(x) else None
