"""A mechanism parsed once (:class:`Mechanism`) and the typed forms of the
strings the CLI takes: effects (``--effect``), distributions and varied
parameters (``--vary``), failure criteria (``--fail``).

Each typed object's ``str()`` is the CLI's syntax; strings are still
accepted wherever a typed object is, and both are checked by the Rust
validator the CLI uses (the same refusals, the same words, the Python
argument named where the CLI names its flag). A typed object also checks
its fields where it is written: their types, and for the laws, ``Vary``
and the criteria the values the CLI's parser refuses whatever the
mechanism (an ``InputError`` naming ``Class.field``, the value and what
was expected); what depends on the mechanism (a joint it lacks, a time
beyond its ``duration_s``) is checked by the command."""

from __future__ import annotations

import math as _math
import os as _os
import sys as _sys
import warnings as _warnings
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

from . import _native
from ._checks import _finite, _positive, _read_text, _real, checked
from ._errors import InputError
from ._results import Trajectory


def _num(x: float) -> str:
    """A number as the CLI's parser reads it (``repr`` of the float)."""
    return repr(float(x))


# ---- effects (docs/spec/physics.md section 6) -----------------------------


@dataclass(frozen=True)
@checked
class Coulomb:
    """``coulomb_friction``: an extra Coulomb friction ``torque_nm`` [N·m]
    at ``joint`` (1-based)."""

    joint: int
    torque_nm: float

    def __str__(self) -> str:
        return f"coulomb_friction:joint={self.joint}:value={_num(self.torque_nm)}"


@dataclass(frozen=True)
@checked
class Viscous:
    """``viscous_damping``: ``nms_per_rad`` [N·m·s/rad] at ``joint``."""

    joint: int
    nms_per_rad: float

    def __str__(self) -> str:
        return f"viscous_damping:joint={self.joint}:value={_num(self.nms_per_rad)}"


@dataclass(frozen=True)
@checked
class QuadraticDamping:
    """``quadratic_damping``: ``c`` [N·m·s²/rad²] at ``joint``, the torque
    ``-c φ̇|φ̇|``."""

    joint: int
    c: float

    def __str__(self) -> str:
        return f"quadratic_damping:joint={self.joint}:value={_num(self.c)}"


@dataclass(frozen=True)
@checked
class Stribeck:
    """``stribeck_friction``: kinetic ``torque_nm`` [N·m] at ``joint`` with a
    break-away ``excess_nm`` [N·m] and Stribeck velocity ``stribeck_rad_s``
    [rad/s]."""

    joint: int
    torque_nm: float
    excess_nm: float
    stribeck_rad_s: float

    def __str__(self) -> str:
        return (
            f"stribeck_friction:joint={self.joint}:value={_num(self.torque_nm)}"
            f":excess_nm={_num(self.excess_nm)}:stribeck_rad_s={_num(self.stribeck_rad_s)}"
        )


@dataclass(frozen=True)
@checked
class SpringSoftening:
    """``spring_softening``: the spring of ``joint`` scaled by ``1 - fraction``
    (``fraction`` [1], below 1)."""

    joint: int
    fraction: float

    def __str__(self) -> str:
        return f"spring_softening:joint={self.joint}:value={_num(self.fraction)}"


@dataclass(frozen=True)
@checked
class Harness:
    """``harness_stiffness``: ``nm_per_rad`` [N·m/rad] about the stowed angle
    of ``joint``."""

    joint: int
    nm_per_rad: float

    def __str__(self) -> str:
        return f"harness_stiffness:joint={self.joint}:value={_num(self.nm_per_rad)}"


@dataclass(frozen=True)
@checked
class LatchDetent:
    """``latch_detent``: ``torque_nm`` [N·m] within 3° of the latch of
    ``joint``."""

    joint: int
    torque_nm: float

    def __str__(self) -> str:
        return f"latch_detent:joint={self.joint}:value={_num(self.torque_nm)}"


@dataclass(frozen=True)
@checked
class AirDrag:
    """``air_drag``: ``k_kg_m2`` [kg/m²], the whole wing."""

    k_kg_m2: float

    def __str__(self) -> str:
        return f"air_drag:value={_num(self.k_kg_m2)}"


@dataclass(frozen=True)
@checked
class RigTilt:
    """``rig_tilt``: gravity ``g_m_s2`` [m/s²] in direction ``alpha_deg``
    [deg], the whole wing."""

    g_m_s2: float
    alpha_deg: float = 0.0

    def __str__(self) -> str:
        return f"rig_tilt:value={_num(self.g_m_s2)}:alpha_deg={_num(self.alpha_deg)}"


@dataclass(frozen=True)
@checked
class EncoderOffset:
    """``encoder_offset``: ``deg`` [deg] added to the reading of ``joint``
    (the sensor only)."""

    joint: int
    deg: float

    def __str__(self) -> str:
        return f"encoder_offset:joint={self.joint}:value={_num(self.deg)}"


@dataclass(frozen=True)
@checked
class PlungerWeakening:
    """``plunger_weakening``: the ball plunger of the physical latch of
    ``joint`` scaled by ``1 - fraction`` [1]."""

    joint: int
    fraction: float

    def __str__(self) -> str:
        return f"plunger_weakening:joint={self.joint}:value={_num(self.fraction)}"


@dataclass(frozen=True)
@checked
class MagnetWeakening:
    """``magnet_weakening``: the magnet of the physical latch of ``joint``
    scaled by ``1 - fraction`` [1]."""

    joint: int
    fraction: float

    def __str__(self) -> str:
        return f"magnet_weakening:joint={self.joint}:value={_num(self.fraction)}"


Effect = Union[
    Coulomb,
    Viscous,
    QuadraticDamping,
    Stribeck,
    SpringSoftening,
    Harness,
    LatchDetent,
    AirDrag,
    RigTilt,
    EncoderOffset,
    PlungerWeakening,
    MagnetWeakening,
]
"""A typed effect; its ``str()`` is the ``--effect`` syntax."""

EFFECT_TYPES: Tuple[type, ...] = (
    Coulomb,
    Viscous,
    QuadraticDamping,
    Stribeck,
    SpringSoftening,
    Harness,
    LatchDetent,
    AirDrag,
    RigTilt,
    EncoderOffset,
    PlungerWeakening,
    MagnetWeakening,
)

# ---- distributions, varied parameters, failure criteria -------------------


@dataclass(frozen=True)
@checked
class Normal:
    """``normal(mean, sd)``: ``mean`` finite, ``sd`` finite and above 0."""

    mean: float
    sd: float

    def _check_values(self) -> None:
        _finite("Normal.mean", self.mean)
        _positive("Normal.sd", self.sd, "a positive finite number (a standard deviation)")

    def __str__(self) -> str:
        return f"normal({_num(self.mean)},{_num(self.sd)})"


@dataclass(frozen=True)
@checked
class LogNormal:
    """``lognormal(median, sigma_ln)``: both finite and above 0."""

    median: float
    sigma_ln: float

    def _check_values(self) -> None:
        _positive("LogNormal.median", self.median)
        _positive("LogNormal.sigma_ln", self.sigma_ln, "a positive finite number (the standard deviation of ln x)")

    def __str__(self) -> str:
        return f"lognormal({_num(self.median)},{_num(self.sigma_ln)})"


@dataclass(frozen=True)
@checked
class Uniform:
    """``uniform(lo, hi)``: both finite, ``hi`` above ``lo``."""

    lo: float
    hi: float

    def _check_values(self) -> None:
        lo = _finite("Uniform.lo", self.lo)
        _above("Uniform.hi", _finite("Uniform.hi", self.hi), lo)

    def __str__(self) -> str:
        return f"uniform({_num(self.lo)},{_num(self.hi)})"


@dataclass(frozen=True)
@checked
class TruncNormal:
    """``truncnormal(mean, sd, lo, hi)``: a normal law kept to ``[lo, hi]``;
    ``mean`` finite, ``sd`` finite and above 0, ``hi`` above ``lo`` (a
    bound may be infinite: ``lo = -math.inf`` or ``hi = math.inf`` keeps
    one side only)."""

    mean: float
    sd: float
    lo: float
    hi: float

    def _check_values(self) -> None:
        _finite("TruncNormal.mean", self.mean)
        _positive("TruncNormal.sd", self.sd, "a positive finite number (a standard deviation)")
        lo = _real("TruncNormal.lo", self.lo)
        if _math.isnan(lo) or lo == _math.inf:
            raise InputError(f"TruncNormal.lo: expected a number below inf (-inf keeps no lower bound), got {lo}")
        _above("TruncNormal.hi", _real("TruncNormal.hi", self.hi), lo)

    def __str__(self) -> str:
        return f"truncnormal({_num(self.mean)},{_num(self.sd)},{_num(self.lo)},{_num(self.hi)})"


Distribution = Union[Normal, LogNormal, Uniform, TruncNormal]
"""A typed distribution; its ``str()`` is the law of ``--vary``."""

DISTRIBUTION_TYPES: Tuple[type, ...] = (Normal, LogNormal, Uniform, TruncNormal)


def _above(name: str, hi: float, lo: float) -> None:
    """An upper bound above the lower one (both read already)."""
    if not hi > lo:
        raise InputError(f"{name}: expected a number above lo = {lo}, got {hi}")


@dataclass(frozen=True)
@checked
class Vary:
    """A varied parameter: ``name`` an effect (``"coulomb_friction"``) or a
    mechanism parameter (``"panel_mass"``, ``"panel_inertia"``,
    ``"spring_preload"``, ``"spring_stiffness"``), at ``joint`` (from 1;
    ``None`` for a global effect), drawn from ``law`` (a :class:`Normal`,
    :class:`LogNormal`, :class:`Uniform` or :class:`TruncNormal`).
    ``str()``: ``--vary``'s syntax.

    Checked where it is written by the ``--vary`` parser the CLI uses:
    an unknown ``name``, a joint given to a global effect or missing for a
    per-joint one is an ``InputError`` naming ``Vary.name`` or
    ``Vary.joint``. Whether the mechanism has that joint is checked by the
    command that takes it."""

    name: str
    joint: Optional[int]
    law: Distribution

    def _check_values(self) -> None:
        if not isinstance(self.law, DISTRIBUTION_TYPES):
            raise InputError(
                f"Vary.law: expected a Normal, LogNormal, Uniform or TruncNormal, "
                f"got {type(self.law).__name__} {self.law!r}"
            )
        if self.joint is not None and self.joint < 1:
            raise InputError(f"Vary.joint: expected a joint number from 1 (None for a global effect), got {self.joint}")
        why = _native.check_vary(str(self))
        if why is None:
            return
        # The law was checked by its own class: what the parser refuses is
        # the name, or the joint when another joint (or none) would do.
        law = str(self.law)
        joint_only = any(_native.check_vary(f"{self.name}{at}:{law}") is None for at in (":joint=1", ""))
        raise InputError(f"Vary.{'joint' if joint_only else 'name'}: {why}")

    def __str__(self) -> str:
        at = "" if self.joint is None else f":joint={self.joint}"
        return f"{self.name}{at}:{self.law}"


@dataclass(frozen=True)
@checked
class NotLatched:
    """``not_latched``: a joint not latched by the end of the run fails."""

    def __str__(self) -> str:
        return "not_latched"


@dataclass(frozen=True)
@checked
class NotHeld:
    """``not_held``: a joint its latch does not hold at the end of the run
    fails (a ball plunger short of its crest, a pawl out of its notch),
    whatever the latch's switch reads; with an ideal latch, ``not_latched``."""

    def __str__(self) -> str:
        return "not_held"


@dataclass(frozen=True)
@checked
class LatchRate:
    """``latch_rate>X``: a joint latching faster than ``above_deg_s``
    [deg/s] (finite, above 0) fails."""

    above_deg_s: float

    def _check_values(self) -> None:
        _positive("LatchRate.above_deg_s", self.above_deg_s, "a positive finite rate [deg/s]")

    def __str__(self) -> str:
        return f"latch_rate>{_num(self.above_deg_s)}"


@dataclass(frozen=True)
@checked
class LatchTime:
    """``time>X``: a joint latching later than ``above_s`` [s] (finite,
    above 0; below the mechanism's ``duration_s``, which the command that
    takes it checks) fails."""

    above_s: float

    def _check_values(self) -> None:
        _positive("LatchTime.above_s", self.above_s, "a positive finite time [s]")

    def __str__(self) -> str:
        return f"time>{_num(self.above_s)}"


Criterion = Union[NotLatched, NotHeld, LatchRate, LatchTime]
"""A typed failure criterion; its ``str()`` is ``--fail``'s syntax."""

EffectLike = Union[str, Effect]
VaryLike = Union[str, Vary]
CriterionLike = Union[str, Criterion]

_TYPED: Dict[str, Tuple[type, ...]] = {
    "effects": EFFECT_TYPES,
    "vary": (Vary,),
    "fail": (NotLatched, NotHeld, LatchRate, LatchTime),
}


def strings(name: str, value: Any) -> List[str]:
    """The items of argument ``name`` (strings or typed objects) as the
    CLI's strings; refuses a single string (which Python would iterate
    character by character) and other types, naming ``name[i]``."""
    typed = _TYPED.get(name, ())
    if isinstance(value, (str, bytes)):
        raise InputError(f"{name}: expected a list of strings, e.g. [{value!r}], got a single string")
    if isinstance(value, typed):
        raise InputError(f"{name}: expected a list, e.g. [{value!r}], got a single {type(value).__name__}")
    try:
        items = list(value)
    except TypeError:
        raise InputError(f"{name}: expected a list of strings, got {type(value).__name__}") from None
    out = []
    for i, v in enumerate(items):
        if isinstance(v, typed):
            out.append(str(v))
        elif isinstance(v, str):
            out.append(v)
        else:
            kinds = " or ".join(["a string"] + [t.__name__ for t in typed][:3] + (["..."] if len(typed) > 3 else []))
            raise InputError(f"{name}[{i}]: expected {kinds}, got {type(v).__name__} {v!r}")
    return out


# ---- the mechanism ---------------------------------------------------------


@dataclass(frozen=True)
class Panel:
    """``[[panel]]``: length [m], mass [kg], centre of mass from the hinge
    [m], inertia about the centre of mass [kg·m²], and the declared
    tolerances of its mass and inertia, half bands [%] (0: none declared;
    ``docs/diagnosis.md``, "What the drawing's tolerances add")."""

    length_m: float
    mass_kg: float
    com_m: float
    inertia_kgm2: float
    mass_tolerance_pct: float
    inertia_tolerance_pct: float


@dataclass(frozen=True)
class Joint:
    """``[[joint]]``: the stowed angle [deg] (the latch at 0), the spring's
    kind (``"linear"``, ``"tape"``, ``"curve"``) and count, the friction
    of the file: Coulomb [N·m], viscous [N·m·s/rad], and the hinge's
    declared free-play, a half band [deg] (0: none declared;
    ``docs/diagnosis.md``, "Free-play held to one side"), and the
    spring's declared torque tolerance, a half band [%] (0: none declared;
    ``docs/diagnosis.md``, "What the drawing's tolerances add")."""

    stowed_deg: float
    spring: str
    spring_count: int
    coulomb_nm: float
    viscous_nms: float
    free_play_deg: float
    spring_tolerance_pct: float


@dataclass(frozen=True)
class Latch:
    """``[joint.latch]`` of a physical latch: the switch's travel [deg],
    a magnet or not, the pawl's breaking torque [N·m] (``None``: a ball
    plunger)."""

    switch_travel_deg: float
    magnet: bool
    pawl_breaking_torque_nm: Optional[float]


@dataclass(frozen=True)
class Trolley:
    """A rig trolley: the panel it carries (1-based), its offload point [m],
    mass [kg], wire length [m]."""

    panel: int
    offload_m: float
    mass_kg: float
    wire_m: float


@dataclass(frozen=True)
class Rig:
    """``[rig]``: enabled or not, gravity [m/s²], static and dynamic
    friction coefficients [1], the trolleys."""

    enabled: bool
    gravity_m_s2: float
    static_mu: float
    dynamic_mu: float
    trolleys: Tuple[Trolley, ...]


PathLike = Union[str, "_os.PathLike[str]"]
"""A file name: ``str`` or ``pathlib.Path``."""


def _user_level() -> int:
    """The ``stacklevel`` of a warning raised by the caller of this
    function that points at the first frame outside the package: the
    user's line, whichever of the package's functions led there."""
    package = _os.path.dirname(__file__)
    frame, level = _sys._getframe(1), 1
    while frame.f_back is not None and _os.path.dirname(frame.f_code.co_filename) == package:
        frame, level = frame.f_back, level + 1
    return level


class Mechanism:
    """A mechanism file parsed once (``docs/spec/formats.md``), its parts as
    typed attributes; ``simulate`` runs it without reading the file again.
    Pickles as its text (what a Dask worker is sent)."""

    name: str
    description: str
    duration_s: float
    sample_hz: float
    settle_s: float
    panels: Tuple[Panel, ...]
    joints: Tuple[Joint, ...]
    latches: Tuple[Optional[Latch], ...]
    """One per joint; ``None`` for the ideal latch."""
    rig: Optional[Rig]
    truss: bool
    """True for a wing with a ``[truss]`` (closed loops)."""

    def __init__(self, model: _native.Model) -> None:
        self._model = model
        d = model.describe()
        self.name = d["name"]
        self.description = d["description"]
        self.duration_s = d["duration_s"]
        self.sample_hz = d["sample_hz"]
        self.settle_s = d["settle_s"]
        self.truss = d["truss"]
        self.panels = tuple(Panel(**p) for p in d["panels"])
        self.joints = tuple(Joint(**j) for j in d["joints"])
        self.latches = tuple(None if l is None else Latch(**l) for l in d["latches"])
        r = d["rig"]
        self.rig = None if r is None else Rig(
            enabled=r["enabled"],
            gravity_m_s2=r["gravity_m_s2"],
            static_mu=r["static_mu"],
            dynamic_mu=r["dynamic_mu"],
            trolleys=tuple(Trolley(*t) for t in r["trolleys"]),
        )

    @classmethod
    def from_toml(cls, path: PathLike) -> "Mechanism":
        """The mechanism of a TOML file (``MechanismError`` naming the file,
        line and key)."""
        text, p = _read_text("path", path)
        return cls._warned(_native.Model(text, p))

    @classmethod
    def from_str(cls, text: str, source: str = "<string>") -> "Mechanism":
        """The mechanism of TOML ``text``; ``source`` names it in errors."""
        if isinstance(text, _os.PathLike):
            raise InputError(
                f"text: expected the TOML text as str, got the file name {_os.fspath(text)!r}: "
                f"Mechanism.from_toml({_os.fspath(text)!r}) reads the file"
            )
        if not isinstance(text, str):
            raise InputError(f"text: expected the TOML text as str, got {type(text).__name__}")
        name = text.strip()
        if "\n" not in name and "=" not in name and (name.endswith(".toml") or _os.path.isfile(name)):
            raise InputError(
                f"text: expected the TOML text, got the file name {name!r}: Mechanism.from_toml({name!r}) reads the file"
            )
        return cls._warned(_native.Model(text, str(source)))

    @classmethod
    def _warned(cls, model: _native.Model) -> "Mechanism":
        """The mechanism of ``model``, each of its valid but unlikely values
        (a mass in grams, angles in radians, a spring that cannot deploy)
        raised as a ``UserWarning``, as the CLI warns of them."""
        for w in model.implausible():
            _warnings.warn(w, UserWarning, stacklevel=_user_level())
        return cls(model)

    @classmethod
    def _unpickled(cls, text: str, source: str) -> "Mechanism":
        """The mechanism a pickle carried (warned of when it was first read)."""
        return cls(_native.Model(text, source))

    @property
    def toml(self) -> str:
        """The file's text."""
        return self._model.text

    @property
    def source(self) -> str:
        """The file's name (or ``"<string>"``)."""
        return self._model.source

    def __reduce__(self) -> Tuple[Any, ...]:
        return (Mechanism._unpickled, (self.toml, self.source))

    def __repr__(self) -> str:
        return f"Mechanism({self.name!r}, {len(self.panels)} panels, source={self.source!r})"

    def check_effects(self, effects: Sequence[EffectLike]) -> List[str]:
        """The effects checked against this mechanism as the CLI checks
        ``--effect``, in the CLI's syntax; ``InputError`` naming
        ``effects[i]`` and saying what is wrong."""
        return self._model.check_effects("effects", strings("effects", effects))

    def simulate(self, effects: Sequence[EffectLike] = (), sample_hz: Optional[float] = None) -> Trajectory:
        """One deployment (``deploywatch simulate``), with extra effects
        (typed, e.g. ``Coulomb(joint=2, torque_nm=0.5)``, or ``--effect``
        strings), sampled at ``sample_hz`` [Hz] (default: the file's).
        See :func:`deploywatch.simulate`."""
        from ._api import _positive

        effs = strings("effects", effects)
        hz = None if sample_hz is None else _positive("sample_hz", sample_hz)
        t_s, phi, rate, latch, end_s = _native.simulate(self._model, effs, hz)
        return Trajectory(t_s=t_s, phi_deg=phi, rate_deg_s=rate, latch_s=latch, end_s=end_s)
