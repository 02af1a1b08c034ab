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


def _pandas() -> Any:
    """pandas, imported when a ``to_pandas()`` view is asked for (it is not
    a dependency of the package: ``pip install pandas``)."""
    import importlib

    try:
        return importlib.import_module("pandas")
    except ImportError:
        raise ImportError("to_pandas(): pandas is not installed (pip install pandas)") from None


@dataclass(frozen=True, eq=False)
class Trajectory:
    """One simulated deployment (``deploywatch simulate``).

    ``t_s`` (n,) [s]; ``phi_deg`` and ``rate_deg_s`` (n, joints) [deg],
    [deg/s]; ``latch_s`` (joints,) [s], NaN where the joint did not latch;
    ``end_s`` [s] where the run ends, the time of its last sample
    (``t_s[-1]``), whichever simulator ran it: a wing of ideal latches
    that deployed is recorded ``settle_s`` past its last latch; one with
    physical latches, or with a joint that did not latch, up to the
    mechanism's ``duration_s``. The last latch is :attr:`last_latch_s`.
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

    @property
    def last_latch_s(self) -> float:
        """When the wing deployed [s]: the latest of ``latch_s`` once every
        joint latched; NaN when a joint did not latch."""
        if self.latch_s.size == 0 or _np.isnan(self.latch_s).any():
            return math.nan
        return float(self.latch_s.max())

    def to_pandas(self) -> Any:
        """A ``pandas.DataFrame`` view: indexed by ``t_s``, one column per
        joint of angle (``phiJ_deg``) and rate (``rateJ_deg_s``), the run
        CSV's names."""
        pd = _pandas()
        cols: Dict[str, FloatArray] = {}
        for j in range(self.joints):
            cols[f"phi{j + 1}_deg"] = self.phi_deg[:, j]
            cols[f"rate{j + 1}_deg_s"] = self.rate_deg_s[:, j]
        return pd.DataFrame(cols, index=pd.Index(self.t_s, name="t_s"))


@dataclass(frozen=True, eq=False)
class Batch:
    """A batch of deployments, one per row of ``params``
    (:func:`deploywatch.simulate_batch`).

    ``g`` (n,): the limit state, failure iff ``g <= 0``; ``margins``
    (n, modes): the margin of each failure mode (one per ``fail`` criterion
    and joint, the modes of the reliability analysis; a mode failed iff
    its margin ``<= 0``, ``g`` is their minimum); ``latch_s`` [s] and
    ``latch_rate_deg_s`` [deg/s] (n, joints), NaN where not latched (the
    rate: NaN everywhere unless a ``latch_rate>X`` criterion is in
    ``fail``, the only one that needs it sampled);
    ``end_deg`` (n, joints) [deg]: the angle at the end of the run.
    """

    g: FloatArray
    margins: FloatArray
    latch_s: FloatArray
    latch_rate_deg_s: FloatArray
    end_deg: FloatArray

    @property
    def failed(self) -> _npt.NDArray[_np.bool_]:
        """Which rows failed (``g <= 0``)."""
        return self.g <= 0.0


@dataclass(frozen=True)
class Level:
    """One level of subset simulation of a mode: its threshold ``b_k`` of
    the mode's margin (0 for the last level of a mode reached), the
    conditional probability ``p``, its coefficient of variation ``cov``,
    and the deployments it took."""

    threshold: float
    p: float
    cov: float
    simulations: int


@dataclass(frozen=True)
class ModeResult:
    """Subset simulation of one failure mode (``mode``, e.g.
    ``"not_latched at joint 1"``): ``p`` the estimate of its probability
    (reached) or of its last level's (not reached), ``cov``, ``converged``
    (its thresholds reached 0), ``stop`` (why its levels stopped:
    ``reached``, ``stalled``, ``negligible`` or ``levels``), ``counted``
    (the share of its failures no earlier mode has: the system counts
    ``p * counted``), ``simulations``, ``levels``."""

    mode: str
    p: float
    cov: float
    converged: bool
    stop: str
    counted: float
    simulations: int
    levels: Tuple[Level, ...]


@dataclass(frozen=True)
class DesignPoint:
    """A design point of FORM (importance sampling): the most likely point
    of the failure domain of ``mode``, its ``beta = |u|``, standard normal
    point ``u``, ``parameters`` (label -> value) and the deployments the
    search took."""

    mode: str
    beta: float
    u: Tuple[float, ...]
    parameters: Mapping[str, float]
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
class FixedEffect:
    """An effect every deployment carries as found, not drawn (a
    diagnosis's ``torque_table`` read by ``from_``): ``effect`` in the
    ``--effect`` syntax, ``source`` where it comes from and which values
    were taken (each knot at the end of its band that resists the
    deployment)."""

    effect: str
    source: str


@dataclass(frozen=True)
class Estimate:
    """One method's estimate inside an ``auto`` result
    (:attr:`Reliability.estimates`), and the part of every
    :class:`Reliability` that its method gives."""

    method: str
    p_fail: float
    cov: float
    ci95: Tuple[float, float]
    simulations: int
    failures: int
    converged: bool
    most_likely_failure: Optional[FailurePoint]
    modes: Tuple[ModeResult, ...] = ()
    design_points: Tuple[DesignPoint, ...] = ()
    unreached: Tuple[str, ...] = ()

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Estimate":
        """The estimate from its JSON object (``estimates.is`` or
        ``estimates.subset`` of the CLI's file)."""
        return cls(**_body(d))

    def to_dict(self) -> Dict[str, Any]:
        """Its JSON object, as the CLI writes it."""
        return _body_json(self)


@dataclass(frozen=True, kw_only=True)
class Reliability(Estimate):
    """The result of :func:`deploywatch.reliability`, field for field the
    JSON of ``deploywatch reliability --json`` (``to_dict()`` gives that
    JSON's dict back; ``from_dict`` reads it): the :class:`Estimate` of its
    method and the problem it answers.

    ``method``: ``auto``, ``is``, ``subset`` or ``mc``; ``p_fail`` the
    failure probability, ``cov`` its coefficient of variation, ``ci95`` its
    95 % interval, ``simulations`` the deployments run, ``failures`` the
    failed ones among the samples (mc, is) or in the modes' last levels
    (subset), ``converged``, ``most_likely_failure`` (None if none failed);
    ``modes``: subset simulation of each failure mode (subset; empty
    otherwise); ``design_points`` and ``unreached`` (is: the design points
    sampled around, the modes whose boundary FORM did not find);
    ``mechanism``, ``seed``, ``vary``, ``fail``, ``corr`` and ``fixed``
    (the :class:`FixedEffect` s of ``from_``): the problem (keyword-only); ``estimates`` and ``agree`` (auto: the :class:`Estimate`
    of ``is`` and of ``subset``, and whether they agree within their 95 %
    intervals, None when neither saw a failure; ``{}`` and None otherwise).
    ``warnings``: what the reader must not miss, the words the CLI prints
    on stderr (methods that disagree, modes not reached, a c.o.v. above
    ``target_cov``, a verdict the latches' switches decide while the
    latches hold), each also raised as a ``UserWarning``; ``()`` when none.
    ``extra``: any field of the JSON this version does not know, kept as it
    came.
    """

    mechanism: str
    seed: int
    vary: Tuple[str, ...]
    fail: Tuple[str, ...]
    corr: Tuple[str, ...]
    fixed: Tuple[FixedEffect, ...] = ()
    estimates: Mapping[str, Estimate] = field(default_factory=dict)
    agree: Optional[bool] = None
    warnings: Tuple[str, ...] = ()
    extra: Mapping[str, Any] = field(default_factory=dict)

    _KNOWN = (
        "mechanism", "method", "seed", "vary", "fail", "corr", "fixed", "p_fail", "cov",
        "ci95", "simulations", "failures", "converged", "most_likely_failure",
        "modes", "design_points", "unreached", "estimates", "agree", "warnings",
    )

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Reliability":
        """The result from the JSON object of ``deploywatch reliability
        --json`` (as ``json.load`` gives it) or from the extension."""
        checks = d.get("estimates") or {}
        agree = d.get("agree")
        return cls(
            mechanism=str(d["mechanism"]),
            seed=int(d["seed"]),
            vary=tuple(d["vary"]),
            fail=tuple(d["fail"]),
            corr=tuple(d.get("corr", ())),
            fixed=tuple(
                FixedEffect(str(f["effect"]), str(f["source"])) for f in d.get("fixed", ())
            ),
            estimates={str(k): Estimate.from_dict(v) for k, v in checks.items()},
            agree=None if agree is None else bool(agree),
            warnings=tuple(str(w) for w in d.get("warnings", ())),
            extra={k: v for k, v in d.items() if k not in cls._KNOWN},
            **_body(d),
        )

    def to_dict(self) -> Dict[str, Any]:
        """The JSON object ``deploywatch reliability --json`` writes for the
        same analysis (the same keys in the same order: ``modes`` when
        there are some, ``design_points`` and ``unreached`` for is,
        ``estimates`` and ``agree`` for auto, then ``warnings``)."""
        out: Dict[str, Any] = {
            "mechanism": self.mechanism,
            "method": self.method,
            "seed": self.seed,
            "vary": list(self.vary),
            "fail": list(self.fail),
            "corr": list(self.corr),
            "fixed": [{"effect": f.effect, "source": f.source} for f in self.fixed],
        }
        out.update(_body_json(self))
        if self.estimates:
            out["estimates"] = {k: e.to_dict() for k, e in self.estimates.items()}
            out["agree"] = self.agree
        out["warnings"] = list(self.warnings)
        out.update(self.extra)
        return out


def _params(d: Mapping[str, Any]) -> Dict[str, float]:
    return {str(k): float(v) for k, v in d.items()}


def _body(d: Mapping[str, Any]) -> Dict[str, Any]:
    """The fields every method's JSON object has, as keyword arguments of
    :class:`Estimate` (and of :class:`Reliability`)."""
    point = d.get("most_likely_failure")
    lo, hi = d["ci95"]
    return {
        "method": str(d["method"]),
        "p_fail": _num(d["p_fail"]),
        "cov": _num(d["cov"], none=math.inf),
        "ci95": (_num(lo), _num(hi)),
        "simulations": int(d["simulations"]),
        "failures": int(d["failures"]),
        "converged": bool(d["converged"]),
        "most_likely_failure": None if point is None else FailurePoint(
            parameters=_params(point["parameters"]),
            u=tuple(float(x) for x in point["u"]),
            beta=_num(point["beta"]),
            g=_num(point["g"]),
        ),
        "modes": tuple(
            ModeResult(
                mode=str(m["mode"]), p=_num(m["p"]), cov=_num(m["cov"], none=math.inf),
                converged=bool(m["converged"]), stop=str(m["stop"]), counted=_num(m["counted"]),
                simulations=int(m["simulations"]),
                levels=tuple(
                    Level(_num(lv["threshold"]), _num(lv["p"]),
                          _num(lv["cov"], none=math.inf), int(lv["simulations"]))
                    for lv in m["levels"]
                ),
            )
            for m in d.get("modes", ())
        ),
        "design_points": tuple(
            DesignPoint(
                mode=str(p["mode"]), beta=_num(p["beta"], none=math.inf),
                u=tuple(float(x) for x in p["u"]), parameters=_params(p["parameters"]),
                simulations=int(p["simulations"]),
            )
            for p in d.get("design_points", ())
        ),
        "unreached": tuple(str(m) for m in d.get("unreached", ())),
    }


def _body_json(e: Estimate) -> Dict[str, Any]:
    """The method's part of the CLI's JSON object, in its key order."""
    point = e.most_likely_failure
    out: Dict[str, Any] = {
        "method": e.method,
        "p_fail": _json(e.p_fail),
        "cov": _json(e.cov),
        "ci95": [_json(x) for x in e.ci95],
        "simulations": e.simulations,
        "failures": e.failures,
        "converged": e.converged,
        "most_likely_failure": None if point is None else {
            "parameters": dict(point.parameters),
            "u": list(point.u),
            "beta": _json(point.beta),
            "g": _json(point.g),
        },
    }
    if e.modes:
        out["modes"] = [
            {"mode": m.mode, "p": _json(m.p), "cov": _json(m.cov), "converged": m.converged,
             "stop": m.stop, "counted": _json(m.counted), "simulations": m.simulations,
             "levels": [
                 {"threshold": _json(lv.threshold), "p": _json(lv.p), "cov": _json(lv.cov),
                  "simulations": lv.simulations}
                 for lv in m.levels
             ]}
            for m in e.modes
        ]
    if e.method == "is":
        out["design_points"] = [
            {"mode": p.mode, "beta": _json(p.beta), "u": list(p.u),
             "parameters": dict(p.parameters), "simulations": p.simulations}
            for p in e.design_points
        ]
        out["unreached"] = list(e.unreached)
    return out


def _num(x: Any, none: float = math.nan) -> float:
    """A float of the JSON, where ``null`` stands for a value JSON cannot
    hold (serde_json writes infinities and NaN as ``null``): ``none``."""
    return none if x is None else float(x)


def _json(x: float) -> Optional[float]:
    """A float as serde_json writes it: ``None`` if not finite."""
    return x if math.isfinite(x) else None
