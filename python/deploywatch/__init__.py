"""deploywatch from Python: spring-driven deployments of spacecraft panels.

- ``Mechanism.from_toml(path)`` / ``Mechanism.from_str(text)``: a mechanism
  parsed once, its panels, joints, latches and rig as typed attributes;
  ``mech.simulate(effects=[Coulomb(joint=2, torque_nm=0.5)])``. Effects,
  distributions (``Vary``) and failure criteria are typed classes whose
  ``str()`` is the CLI's syntax; strings are accepted too, and both are
  checked by the CLI's own validator (same refusals, same words, the
  Python argument named where the CLI names its flag).

- ``simulate(mechanism, effects=())``: one deployment, a :class:`Trajectory`
  of numpy arrays.
- ``simulate_batch(mechanism, vary, params, fail=("not_latched",))``: one
  deployment per row of ``params`` (the loop in Rust on every core, the GIL
  released), a :class:`Batch`: the limit state ``g``, the margin of each
  failure mode, and per joint latch instant, latch rate and end angle.
- ``reliability(mechanism, vary=..., fail=..., method="auto", ...)``: the
  options of ``deploywatch reliability`` as keyword arguments, a
  :class:`Reliability` (``.to_dict()`` is the CLI's JSON). ``executor=``:
  any ``concurrent.futures.Executor`` or a ``dask.distributed.Client``; the
  batches of deployments are submitted there, the analysis runs here. The
  result equals the local one bit for bit.
- ``parameters(...)``: the column order of ``params``.

Errors: every error deploywatch raises is a :class:`DeploywatchError`;
:class:`InputError` (a ``ValueError``; :class:`MechanismError` for the
mechanism file) for bad arguments, :class:`SimulationError` (a
``RuntimeError``) for a deployment that cannot be simulated,
:class:`EvaluatorError` for an executor's unusable answer. They pickle with
their message and cause, so one raised on a Dask worker arrives as itself.

docs/reliability.md (sections 3 and 4) shows the package at work, on one
machine and on a Dask cluster.
"""

from . import _native
from ._api import Executor, Future, MechanismLike, parameters, reliability, simulate, simulate_batch
from ._model import (
    AirDrag,
    Coulomb,
    Criterion,
    CriterionLike,
    Distribution,
    Effect,
    EffectLike,
    EncoderOffset,
    Harness,
    Joint,
    Latch,
    LatchDetent,
    LatchRate,
    LatchTime,
    LogNormal,
    MagnetWeakening,
    Mechanism,
    Normal,
    NotHeld,
    NotLatched,
    Panel,
    PathLike,
    PlungerWeakening,
    QuadraticDamping,
    Rig,
    RigTilt,
    SpringSoftening,
    Stribeck,
    Trolley,
    TruncNormal,
    Uniform,
    Vary,
    VaryLike,
    Viscous,
)
from ._commands import CommandResult, Diagnosis, Hil, Identification, Margins, Replay, diagnose, hil, identify, margin, replay
from ._errors import (
    DeploywatchError,
    EvaluatorError,
    InputError,
    MechanismError,
    MissingFileError,
    SimulationError,
)
from ._monitor import Monitor, MonitorStatus, Sample
from ._results import (
    Batch,
    DesignPoint,
    Estimate,
    FailurePoint,
    FixedEffect,
    FloatArray,
    Level,
    ModeResult,
    Reliability,
    Trajectory,
)

__version__: str = _native.__version__
"""The package's version (that of the Rust crates it is built from)."""

__all__ = [
    "Mechanism",
    "Monitor",
    "MonitorStatus",
    "Sample",
    "Panel",
    "Joint",
    "Latch",
    "Rig",
    "Trolley",
    "Effect",
    "EffectLike",
    "Coulomb",
    "Viscous",
    "QuadraticDamping",
    "Stribeck",
    "SpringSoftening",
    "Harness",
    "LatchDetent",
    "AirDrag",
    "RigTilt",
    "EncoderOffset",
    "PlungerWeakening",
    "MagnetWeakening",
    "Distribution",
    "Normal",
    "LogNormal",
    "Uniform",
    "TruncNormal",
    "Vary",
    "VaryLike",
    "Criterion",
    "CriterionLike",
    "NotLatched",
    "NotHeld",
    "LatchRate",
    "LatchTime",
    "MechanismLike",
    "simulate",
    "simulate_batch",
    "diagnose",
    "identify",
    "margin",
    "replay",
    "hil",
    "CommandResult",
    "Diagnosis",
    "Identification",
    "Margins",
    "Replay",
    "Hil",
    "reliability",
    "parameters",
    "Trajectory",
    "Batch",
    "Reliability",
    "Estimate",
    "ModeResult",
    "Level",
    "DesignPoint",
    "FailurePoint",
    "FixedEffect",
    "FloatArray",
    "PathLike",
    "Executor",
    "Future",
    "DeploywatchError",
    "InputError",
    "MechanismError",
    "MissingFileError",
    "SimulationError",
    "EvaluatorError",
]
