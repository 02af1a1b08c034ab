"""Campaigns from an engine deploywatch did not write, with what real wings
have and the reference model lacks, and a scorer of `deploywatch diagnose`
on them (docs/diagnosis.md, "Campaigns of another engine").

Each campaign is a directory: two mechanism files (the reference physics
of docs/spec/physics.md as a designer would draw them), two run CSVs
(docs/spec/formats.md, "Run: CSV") made by MuJoCo, and ``truth.json``
(never read by the diagnosis): the hidden named effect (0 or 1 of
``coulomb_friction``, ``viscous_damping``, ``spring_softening`` at one
joint) and the nuisances drawn for the case.

The MuJoCo wing is the second opinion's (python/tests/second_opinion.py:
planar hinge chain, gravity off, ideal latch of physics.md §5 located by
re-stepping and applied as the plastic impulse on MuJoCo's mass matrix,
then held by a joint equality) with, drawn per case:

- **flexible panels**: each panel two bodies joined by a hinge whose
  stiffness puts the deployed wing's first mode (every joint latched) at
  4–15 Hz, and whose damping (stiffness-proportional) gives that mode
  1–3 % of critical;
- **hinge free-play**: between the spring/encoder side of a hinge (a small
  body of inertia ``SPRING_SIDE_KGM2``) and its panel, a dead band of
  ±0.05–0.2° (a MuJoCo joint limit); the spring and the encoder are on
  the spring side, the latch, the friction and the hidden effect on the
  panel's angle; the spring side's mass (``SPRING_SIDE_KG``) and inertia
  are hinge hardware the drawing counts in its panel, taken out of the
  panel body (``panel_without_spring_side``) so that the wing's mass
  properties are the drawing's; each mechanism file declares the
  drawing's free-play, ``free_play_deg = DRAWN_FREE_PLAY_DEG`` at every
  joint (the most any hinge has), as a user's drawing would;
- with ``--as-built``, **the wing as built**: each panel's mass and
  inertia and each joint's spring torque drawn uniformly within the
  tolerances its drawing declares, one draw for the two runs of a
  campaign (one wing, a hinge added), from a generator of its own so that
  the case's other draws do not depend on it (without it the wing is
  built at its drawing's nominal values, within those tolerances too);
- **encoder latency** of 0 to 1 sample, and **time-stamp jitter**: each
  sample taken at its stamp plus a normal error of 1–5 % of the period
  (σ), the stamp written as nominal; latch switches are not delayed;
- the reference sensor of physics.md §7 (σ 0.02°, 14-bit rounding).

Every drawing declares the tolerances of its wing (this project's
extension of formats.md): ``mass_tolerance_pct = MASS_TOLERANCE_PCT`` and
``inertia_tolerance_pct = INERTIA_TOLERANCE_PCT`` of every panel,
``spring_tolerance_pct = SPRING_TOLERANCE_PCT`` of every joint.

A wing the nuisances swing past a full turn is drawn again. The hidden effect is drawn (log-uniform, as tests/src/hidden_effect.rs)
until it moves the runs, against the same wing without it, by at least
``MIN_EFFECT_RMS_DEG`` RMS (above the noise) and by at least what the
drawing's spring tolerances do (``tolerance_floor``: every joint's spring
at the worse edge of its band, in quadrature; above the tolerances),
twelve draws at most (then nothing is hidden).

    .venv/bin/python python/examples/outside_engine.py generate DIR N [FIRST_SEED] [--only NUISANCE] [--as-built]
    .venv/bin/python python/examples/outside_engine.py score DIR [DEPLOYWATCH]
    .venv/bin/python python/examples/outside_engine.py campaigns N [FIRST_SEED] [--only NUISANCE] [--as-built] [--keep DIR]
    .venv/bin/python python/examples/outside_engine.py ablation N [FIRST_SEED [STEP]]

``--only`` keeps one nuisance (``flex``, ``freeplay``, ``latency``,
``jitter``, ``asbuilt``, or ``none``) and turns the others off: what each one does to
the answer, one at a time. ``score`` runs ``deploywatch diagnose`` on
every campaign of DIR and prints one line per campaign and the counts;
``campaigns`` generates N campaigns in a temporary directory and scores
them (the command of docs/measured.md; ``--keep DIR`` keeps them in DIR
and resumes: a campaign or diagnosis already there is reused);
``ablation`` does so once per
nuisance alone, and once with none. The binary is
``$CARGO_TARGET_DIR/release/deploywatch`` (``target/`` by default;
``DEPLOYWATCH`` overrides it): ``cargo build --release -p deploywatch-sim``.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
import tomllib
from typing import Any, Dict, List, Optional

import mujoco  # type: ignore[import-untyped]
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

DT_S = 5e-4
"""MuJoCo's step [s] (RK4)."""
W_COUL = 0.01
"""The Coulomb law's regularisation ω_coul [rad/s] (physics.md §4)."""
NOISE_SIGMA_DEG = 0.02
"""The reference encoder's noise σ [deg] (physics.md §7)."""
RESOLUTION_DEG = 360.0 / 16384.0
"""The reference encoder's step [deg] (physics.md §7)."""
SETTLE_S = 0.2
"""A run ends this long after the first sample at or after its last latch (formats.md)."""
MIN_EFFECT_RMS_DEG = 0.3
"""The hidden effect moves the runs by at least this RMS [deg]."""
SPRING_SIDE_KGM2 = 1e-3
"""Inertia of a hinge's spring/encoder side about its axis [kg·m²] (with free-play)."""
DRAWN_FREE_PLAY_DEG = 0.2
"""The hinges' free-play as their drawing declares it, a half band [deg]:
the most a hinge of these wings has (``free_play_deg`` of every joint)."""
MAX_ANGLE_DEG = 360.0
"""A campaign whose wing swings past this angle [deg] is drawn again."""
MAX_REDRAWS = 8
"""Draws of a campaign's wings and nuisances at most."""
SPRING_SIDE_KG = 0.05
"""Mass of a hinge's spring/encoder side [kg] (with free-play), at the hinge."""
REL_TOL = 0.2
"""A found value is right within this fraction of the hidden one."""
MASS_TOLERANCE_PCT = 0.5
"""Every panel's mass as its drawing declares it, a half band [%]."""
INERTIA_TOLERANCE_PCT = 1.0
"""Every panel's inertia as its drawing declares it, a half band [%]."""
SPRING_TOLERANCE_PCT = 2.0
"""Every joint's spring torque as its drawing declares it, a half band [%]."""
NUISANCES = ("flex", "freeplay", "latency", "jitter")
"""What a real wing has that the reference model lacks, drawn per case
(the wing as built, ``asbuilt``, only with ``--as-built`` or ``--only asbuilt``)."""
KINDS = ("none", "coulomb_friction", "viscous_damping", "spring_softening")
"""The hidden effect drawn per case: none, or one of physics.md §6 at one joint."""
UNITS = {"coulomb_friction": "N·m", "viscous_damping": "N·m·s/rad", "spring_softening": "1"}
"""The unit of each kind's value (physics.md §6)."""


@dataclasses.dataclass
class Joint:
    """One joint: stowed angle [deg], linear spring (preload at the
    deployed angle [N·m], stiffness [N·m/rad], per hinge, times
    ``count``), the mechanism's own Coulomb [N·m] and viscous [N·m·s/rad]
    friction."""

    stowed_deg: float
    preload_nm: float
    stiffness_nm_per_rad: float
    count: int
    coulomb_nm: float = 0.0
    viscous_nms: float = 0.0


@dataclasses.dataclass
class Panel:
    """One panel: length [m], mass [kg], centre of mass from the inboard
    hinge [m], inertia about the centre of mass [kg·m²]."""

    length_m: float
    mass_kg: float
    com_m: float
    inertia_kgm2: float


@dataclasses.dataclass
class Wing:
    """One run's mechanism: its name, panels, joints, run length [s] and rate [Hz]."""

    name: str
    panels: List[Panel]
    joints: List[Joint]
    duration_s: float = 6.0
    sample_hz: float = 100.0
    toml: Optional[str] = None


@dataclasses.dataclass
class Nuisance:
    """What the case's wing and sensor have beyond the reference model:
    first deployed mode [Hz] and its damping ratio (0: rigid panels),
    free-play half band per joint [deg] (empty: none), encoder latency
    [samples], jitter σ [fraction of the period], and the wing as built:
    per panel its mass and inertia, per joint its spring torque, each a
    factor on the drawn value (empty: as drawn)."""

    mode_hz: float = 0.0
    mode_zeta: float = 0.0
    freeplay_deg: List[float] = dataclasses.field(default_factory=list)
    latency_samples: float = 0.0
    jitter_frac: float = 0.0
    mass_scale: List[float] = dataclasses.field(default_factory=list)
    inertia_scale: List[float] = dataclasses.field(default_factory=list)
    spring_scale: List[float] = dataclasses.field(default_factory=list)


@dataclasses.dataclass
class Hidden:
    """The hidden effect: kind (``none`` or a name of physics.md §6), joint (1-based), value."""

    kind: str = "none"
    joint: int = 0
    value: float = 0.0


def wing_from_toml(path: str) -> Wing:
    """A linear-spring ideal-latch mechanism file (seed 000's) as a [`Wing`]."""
    text = open(path, encoding="utf-8").read()
    m = tomllib.loads(text)
    panels = [Panel(p["length_m"], p["mass_kg"], p["com_m"], p["inertia_kgm2"]) for p in m["panel"]]
    joints = []
    for j in m["joint"]:
        s = j["spring"]
        if s["kind"] != "linear":
            raise ValueError(f"{path}: only linear springs are modelled here")
        f = j.get("friction", {})
        joints.append(
            Joint(
                j["stowed_deg"],
                s["preload_nm"],
                s["stiffness_nm_per_rad"],
                s.get("count", 1),
                f.get("coulomb_nm", 0.0),
                f.get("viscous_nms", 0.0),
            )
        )
    run = m.get("run", {})
    return Wing(m["name"], panels, joints, run.get("duration_s", 6.0), run.get("sample_hz", 100.0), text)


def random_pair(rng: np.random.Generator, seed: int) -> List[Wing]:
    """A random wing of 2–4 panels (as the second opinion's, fewer panels)
    and its twin with one more hinge at one joint: the two runs of a
    campaign differ by a spring, as seed 000's cases 1 and 3 do."""
    n = int(rng.integers(2, 5))
    panels, joints = [], []
    for _ in range(n):
        length = float(rng.uniform(0.4, 1.0))
        mass = float(rng.uniform(1.0, 5.0))
        panels.append(Panel(length, mass, length * float(rng.uniform(0.4, 0.6)), mass * length**2 / 12.0 * float(rng.uniform(0.8, 1.2))))
        joints.append(
            Joint(
                stowed_deg=float(rng.choice([-1.0, 1.0]) * rng.uniform(60.0, 180.0)),
                preload_nm=float(rng.uniform(0.5, 2.0)),
                stiffness_nm_per_rad=float(rng.uniform(0.1, 0.8)),
                count=int(rng.integers(1, 3)),
            )
        )
    a = Wing(f"outside-{seed}-a", panels, joints)
    b = Wing(f"outside-{seed}-b", panels, [dataclasses.replace(j) for j in joints])
    b.joints[int(rng.integers(0, n))].count += 1
    return [a, b]


def mechanism_toml(w: Wing) -> str:
    """The wing as a deploywatch mechanism file (formats.md)."""
    if w.toml is not None:
        text = re.sub(r"^\[\[joint\]\][^\n]*\n", lambda m: f"{m.group(0)}free_play_deg = {DRAWN_FREE_PLAY_DEG!r}\nspring_tolerance_pct = {SPRING_TOLERANCE_PCT!r}\n", w.toml, flags=re.M)
        return re.sub(
            r"^\[\[panel\]\][^\n]*\n",
            lambda m: f"{m.group(0)}mass_tolerance_pct = {MASS_TOLERANCE_PCT!r}\ninertia_tolerance_pct = {INERTIA_TOLERANCE_PCT!r}\n",
            text,
            flags=re.M,
        )
    out = [f'name = "{w.name}"', 'description = "random ideal-latch wing (python/examples/outside_engine.py)"', ""]
    for p in w.panels:
        out += ["[[panel]]", f"length_m = {p.length_m!r}", f"mass_kg = {p.mass_kg!r}", f"com_m = {p.com_m!r}", f"inertia_kgm2 = {p.inertia_kgm2!r}"]
        out += [f"mass_tolerance_pct = {MASS_TOLERANCE_PCT!r}", f"inertia_tolerance_pct = {INERTIA_TOLERANCE_PCT!r}", ""]
    for j in w.joints:
        out += [
            "[[joint]]",
            f"stowed_deg = {j.stowed_deg!r}",
            f"free_play_deg = {DRAWN_FREE_PLAY_DEG!r}",
            f"spring_tolerance_pct = {SPRING_TOLERANCE_PCT!r}",
            f'spring = {{ kind = "linear", preload_nm = {j.preload_nm!r}, stiffness_nm_per_rad = {j.stiffness_nm_per_rad!r}, count = {j.count} }}',
            f"friction = {{ coulomb_nm = {j.coulomb_nm!r}, viscous_nms = {j.viscous_nms!r} }}",
            "",
        ]
    out += ["[run]", f"duration_s = {w.duration_s}", f"sample_hz = {w.sample_hz}", ""]
    return "\n".join(out)


def panel_without_spring_side(p: Panel) -> Panel:
    """The panel ``p`` as drawn less its hinge's spring side (mass
    ``SPRING_SIDE_KG`` at the hinge, inertia ``SPRING_SIDE_KGM2`` about
    it): what is left, so that the two rigidly together are ``p``."""
    mass = p.mass_kg - SPRING_SIDE_KG
    com = p.mass_kg * p.com_m / mass
    about_hinge = p.inertia_kgm2 + p.mass_kg * p.com_m**2 - SPRING_SIDE_KGM2
    return Panel(p.length_m, mass, com, about_hinge - mass * com**2)


class Model:
    """The wing in MuJoCo: per joint a spring-side hinge ``s`` (with
    free-play, else the panel's own hinge), a dead-band hinge ``d`` (with
    free-play) and, with flexible panels, a flex hinge ``f`` inside the
    panel. ``e[j]`` is the joint angle's row over the dofs (all hinges:
    qpos and qvel share their indices)."""

    def __init__(self, w: Wing, nz: Nuisance, flex_k: Optional[List[float]] = None, flex_c: Optional[List[float]] = None):
        n = len(w.joints)
        self.w, self.nz, self.n = w, nz, n
        fp = bool(nz.freeplay_deg)
        flex = flex_k is not None and flex_c is not None
        ks, cs = flex_k or [], flex_c or []
        body, close, eqs = [], [], []
        for i, (p, j) in enumerate(zip(w.panels, w.joints)):
            if fp:
                # The spring side is hinge hardware the drawing counts in its
                # panel: the panel body is the rest, so that the two together
                # have the drawn panel's mass, centre and inertia.
                p = panel_without_spring_side(p)
            x = 0.0 if i == 0 else (w.panels[i - 1].length_m / 2 if flex else w.panels[i - 1].length_m)
            hinge = f'<joint name="s{i}" type="hinge" axis="0 0 1" stiffness="{j.stiffness_nm_per_rad * j.count!r}" springref="0"/>'
            if fp:
                b = math.radians(nz.freeplay_deg[i])
                body.append(f'<body name="sp{i}" pos="{x!r} 0 0">{hinge}<inertial pos="0 0 0" mass="{SPRING_SIDE_KG!r}" diaginertia="{SPRING_SIDE_KGM2!r} {SPRING_SIDE_KGM2!r} {SPRING_SIDE_KGM2!r}"/>')
                close.append("</body>")
                hinge = f'<joint name="d{i}" type="hinge" axis="0 0 1" limited="true" range="{-b!r} {b!r}" solreflimit="{2 * DT_S!r} 1" solimplimit="0.9999 0.9999 0.001 0.5 2"/>'
                x = 0.0
                eqs.append(f'<joint joint1="s{i}" joint2="d{i}" polycoef="0 -1 0 0 0" active="false" solref="{2 * DT_S!r} 1" solimp="0.9999 0.9999 0.001 0.5 2"/>')
            else:
                eqs.append(f'<joint joint1="s{i}" polycoef="0 0 0 0 0" active="false" solref="{2 * DT_S!r} 1" solimp="0.9999 0.9999 0.001 0.5 2"/>')
            if flex:
                # Two halves of equal mass, centres ±d about the panel's, own
                # inertias so that the whole has the panel's.
                d = 0.15 * p.length_m
                own = (p.inertia_kgm2 - p.mass_kg * d * d) / 2.0
                half = p.mass_kg / 2.0
                body.append(f'<body name="a{i}" pos="{x!r} 0 0">{hinge}<inertial pos="{p.com_m - d!r} 0 0" mass="{half!r}" diaginertia="{own!r} {own!r} {own!r}"/>')
                body.append(
                    f'<body name="b{i}" pos="{p.length_m / 2!r} 0 0"><joint name="f{i}" type="hinge" axis="0 0 1" stiffness="{ks[i]!r}" springref="0" damping="{cs[i]!r}"/>'
                    f'<inertial pos="{p.com_m + d - p.length_m / 2!r} 0 0" mass="{half!r}" diaginertia="{own!r} {own!r} {own!r}"/>'
                )
                close += ["</body>", "</body>"]
            else:
                i_c = p.inertia_kgm2
                body.append(f'<body name="a{i}" pos="{x!r} 0 0">{hinge}<inertial pos="{p.com_m!r} 0 0" mass="{p.mass_kg!r}" diaginertia="{i_c!r} {i_c!r} {i_c!r}"/>')
                close.append("</body>")
        xml = (
            # Every angle of the XML (the band's range) in radians.
            '<mujoco model="wing"><compiler angle="radian"/>'
            f'<option timestep="{DT_S!r}" gravity="0 0 0" integrator="RK4"/>'
            f"<worldbody>{''.join(body)}{''.join(close)}</worldbody>"
            f"<equality>{''.join(eqs)}</equality>"
            "</mujoco>"
        )
        self.m = mujoco.MjModel.from_xml_string(xml)
        self.d = mujoco.MjData(self.m)

        def jid(name: str) -> int:
            return int(self.m.jnt_dofadr[mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_JOINT, name)])

        self.s = [jid(f"s{i}") for i in range(n)]
        self.dd = [jid(f"d{i}") for i in range(n)] if fp else []
        self.f = [jid(f"f{i}") for i in range(n)] if flex else []
        self.e = np.zeros((n, self.m.nv))
        for i in range(n):
            self.e[i, self.s[i]] = 1.0
            if fp:
                self.e[i, self.dd[i]] = 1.0

    def phi(self, q: np.ndarray) -> np.ndarray:
        """Joint angles [rad] (the panels') from positions."""
        out: np.ndarray = self.e @ q
        return out


def flex_stiffness(w: Wing, nz: Nuisance) -> tuple[List[float], List[float]]:
    """Flex hinge stiffness [N·m/rad] and damping [N·m·s/rad], one value
    for every panel, that put the deployed wing's first mode at
    ``nz.mode_hz`` with ``nz.mode_zeta`` of critical damping: with every
    joint latched the flex dofs' mass matrix is ``M_ff`` and their
    stiffness ``k I``, so ω₁² = k / λ_max(M_ff); the damping ``c = 2ζ k / ω₁``
    (proportional to stiffness) gives mode 1 the ratio ζ."""
    n = len(w.joints)
    probe = Model(dataclasses.replace(w), Nuisance(), [1.0] * n, [0.0] * n)
    mujoco.mj_forward(probe.m, probe.d)
    full = np.zeros((probe.m.nv, probe.m.nv))
    mujoco.mj_fullM(probe.m, probe.d, full)
    mff = full[np.ix_(probe.f, probe.f)]
    w1 = 2.0 * math.pi * nz.mode_hz
    k = w1 * w1 * float(np.max(np.linalg.eigvalsh(mff)))
    c = 2.0 * nz.mode_zeta * k / w1
    return [k] * n, [c] * n


@dataclasses.dataclass
class Trace:
    """A run at MuJoCo's step: times [s], encoder-side angles [deg] (n, joints), latch instants [s] (NaN: not latched)."""

    t_s: np.ndarray
    enc_deg: np.ndarray
    latch_s: np.ndarray


def simulate(w: Wing, nz: Nuisance, hidden: Hidden) -> Trace:
    """The wing in MuJoCo from rest (panels at their stowed angles, each
    spring side at the edge of its band that the spring presses) until
    ``w.duration_s`` or ``SETTLE_S`` plus a sample after the last latch."""
    flex_k, flex_c = flex_stiffness(w, nz) if nz.mode_hz > 0 else (None, None)
    md = Model(w, nz, flex_k, flex_c)
    m, d, n = md.m, md.d, md.n
    side = np.sign([j.stowed_deg for j in w.joints])
    soft = np.ones(n)
    coul = np.array([j.coulomb_nm for j in w.joints])
    visc = np.array([j.viscous_nms for j in w.joints])
    hj = hidden.joint - 1
    if hidden.kind == "spring_softening":
        soft[hj] = 1.0 - hidden.value
        m.jnt_stiffness[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"s{hj}")] *= soft[hj]
    elif hidden.kind == "coulomb_friction":
        coul[hj] += hidden.value
    elif hidden.kind == "viscous_damping":
        visc[hj] += hidden.value
    preload = np.array([-s * j.preload_nm * j.count * f for s, j, f in zip(side, w.joints, soft)])
    for i, j in enumerate(w.joints):
        d.qpos[md.s[i]] = math.radians(j.stowed_deg)
        if md.dd:
            # The hold-down holds the panel at the drawn stowed angle; the
            # spring has pushed its own side one band ahead (towards the
            # latch), where it drags the panel, which trails it by the band
            # for the whole deployment.
            b = side[i] * math.radians(nz.freeplay_deg[i])
            d.qpos[md.s[i]] -= b
            d.qpos[md.dd[i]] = b
    free = np.ones(n, dtype=bool)
    latch = np.full(n, np.nan)
    steps = int(round(w.duration_s / DT_S))
    per_sample = 1.0 / (w.sample_hz * DT_S)
    ts, enc = [0.0], [np.degrees(d.qpos[md.s])]
    end_step = steps
    k = 0
    while k < end_step:
        rate = md.e @ d.qvel
        tau = np.where(free, -coul * np.tanh(rate / W_COUL) - visc * rate, 0.0)
        d.qfrc_applied[:] = md.e.T @ tau
        d.qfrc_applied[md.s] += preload
        _step(md, side, free, latch, k * DT_S)
        k += 1
        ts.append(k * DT_S)
        enc.append(np.degrees(d.qpos[md.s]))
        if not free.any() and end_step == steps:
            # Every joint latched: the run ends SETTLE_S after the first
            # sample at or after the last latch (two samples more, for the
            # jitter and the latency).
            first = math.ceil(float(np.nanmax(latch)) * w.sample_hz - 1e-9) / w.sample_hz
            end_step = min(steps, int(math.ceil((first + SETTLE_S) / DT_S + 2 * per_sample)))
    return Trace(np.array(ts), np.array(enc), latch)


def _step(md: Model, side: np.ndarray, free: np.ndarray, latch: np.ndarray, t0: float) -> None:
    """One step; a free joint whose panel angle crosses 0 in it is latched
    at the crossing (the step re-taken to it by the secant rule), and the
    step completed after the impulse."""
    m, d = md.m, md.d
    qpos, qvel, act = d.qpos.copy(), d.qvel.copy(), d.act.copy()
    mujoco.mj_step(m, d)
    phi = md.phi(d.qpos)
    crossed = free & (side * phi <= 0.0)
    if not crossed.any():
        return
    lo, hi = 0.0, DT_S
    f_lo = md.phi(qpos) * side
    f_hi = phi * side
    idx = np.flatnonzero(crossed)
    j = int(idx[np.argmin([f_lo[i] / (f_lo[i] - f_hi[i]) for i in idx])])
    h = DT_S
    for _ in range(40):
        h = lo + (hi - lo) * f_lo[j] / (f_lo[j] - f_hi[j])
        d.qpos[:], d.qvel[:] = qpos, qvel
        d.time = t0
        m.opt.timestep = h
        mujoco.mj_step(m, d)
        f = md.phi(d.qpos) * side
        if abs(f[j]) < 1e-12 or hi - lo < 1e-9:
            break
        if f[j] > 0:
            lo, f_lo = h, f
        else:
            hi, f_hi = h, f
    hit = [int(i) for i in np.flatnonzero(free) if side[i] * md.phi(d.qpos)[i] <= 1e-9]
    _latch(md, free, hit)
    for i in hit:
        latch[i] = t0 + h
    m.opt.timestep = DT_S - h
    if m.opt.timestep > 1e-12:
        mujoco.mj_step(m, d)
        more = [int(i) for i in np.flatnonzero(free) if side[i] * md.phi(d.qpos)[i] <= 0.0]
        if more:
            _latch(md, free, more)
            for i in more:
                latch[i] = t0 + DT_S
    m.opt.timestep = DT_S


def _latch(md: Model, free: np.ndarray, hit: List[int]) -> None:
    """physics.md §5 on the joints latched so far and now:
    v⁺ = v − M⁻¹E (EᵀM⁻¹E)⁻¹ Eᵀ v, E their angle rows; then each new one
    at 0 (on its spring side) and its equality switched on."""
    m, d = md.m, md.d
    mujoco.mj_forward(m, d)
    full = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, full)
    for i in hit:
        free[i] = False
    e = md.e[~free].T
    minv_e = np.linalg.solve(full, e)
    v = d.qvel.copy()
    d.qvel[:] = v - minv_e @ np.linalg.solve(e.T @ minv_e, e.T @ v)
    for i in hit:
        d.qpos[md.s[i]] -= md.phi(d.qpos)[i]
        d.eq_active[i] = 1


def sample(w: Wing, tr: Trace, nz: Nuisance, rng: np.random.Generator) -> np.ndarray:
    """The run as the sensors give it: rows (t, angles [deg], switches),
    the angles at each stamp plus its jitter minus the latency,
    interpolated in the trace, with noise and the 14-bit rounding."""
    period = 1.0 / w.sample_hz
    end = tr.t_s[-1] - 2 * period if np.all(~np.isnan(tr.latch_s)) else tr.t_s[-1]
    last = float(np.nanmax(tr.latch_s)) if np.all(~np.isnan(tr.latch_s)) else None
    count = int(math.floor(end * w.sample_hz + 1e-9)) + 1
    if last is not None:
        first = math.ceil(last * w.sample_hz - 1e-9)
        count = min(count, first + int(round(SETTLE_S * w.sample_hz)) + 1)
    stamp = np.arange(count) * period
    taken = stamp + (rng.normal(0.0, nz.jitter_frac * period, count) if nz.jitter_frac > 0 else 0.0)
    taken[0] = 0.0
    at = np.clip(taken - nz.latency_samples * period, 0.0, tr.t_s[-1])
    n = tr.enc_deg.shape[1]
    angles = np.column_stack([np.interp(at, tr.t_s, tr.enc_deg[:, j]) for j in range(n)])
    angles = angles + rng.normal(0.0, NOISE_SIGMA_DEG, angles.shape)
    angles = np.round(angles / RESOLUTION_DEG) * RESOLUTION_DEG
    switches = np.column_stack([(~np.isnan(tr.latch_s[j])) & (taken >= np.nan_to_num(tr.latch_s[j], nan=np.inf)) for j in range(n)])
    return np.column_stack([stamp, angles, switches.astype(float)])


def write_csv(path: str, w: Wing, rows: np.ndarray, source: str) -> None:
    """A run CSV of formats.md."""
    n = len(w.joints)
    head = ["t_s"] + [f"phi{j + 1}_deg" for j in range(n)] + [f"latch{j + 1}" for j in range(n)]
    with open(path, "w", encoding="utf-8") as f:
        f.write(f'# mechanism = "{w.name}"\n# source = "{source}"\n')
        f.write(",".join(head) + "\n")
        for r in rows:
            f.write(f"{r[0]:.4f}," + ",".join(f"{x:.4f}" for x in r[1 : 1 + n]) + "," + ",".join(str(int(x)) for x in r[1 + n :]) + "\n")


def draw_nuisance(rng: np.random.Generator, n: int, only: Optional[str], built: np.random.Generator, as_built_too: bool) -> Nuisance:
    """Every nuisance drawn (the rng always draws all of them, so a case's
    wing and effect do not depend on ``only``; the wing as built from its
    own generator ``built``); ``only`` keeps one; without it, the wing as
    built only when ``as_built_too``."""
    nz = Nuisance(
        mode_hz=float(rng.uniform(4.0, 15.0)),
        mode_zeta=float(rng.uniform(0.01, 0.03)),
        freeplay_deg=[float(rng.uniform(0.05, DRAWN_FREE_PLAY_DEG)) for _ in range(n)],
        latency_samples=float(rng.uniform(0.0, 1.0)),
        jitter_frac=float(rng.uniform(0.01, 0.05)),
        mass_scale=[1.0 + float(built.uniform(-1.0, 1.0)) * MASS_TOLERANCE_PCT / 100.0 for _ in range(n)],
        inertia_scale=[1.0 + float(built.uniform(-1.0, 1.0)) * INERTIA_TOLERANCE_PCT / 100.0 for _ in range(n)],
        spring_scale=[1.0 + float(built.uniform(-1.0, 1.0)) * SPRING_TOLERANCE_PCT / 100.0 for _ in range(n)],
    )
    if only is None:
        if not as_built_too:
            nz.mass_scale, nz.inertia_scale, nz.spring_scale = [], [], []
        return nz
    keep = Nuisance()
    if only == "flex":
        keep.mode_hz, keep.mode_zeta = nz.mode_hz, nz.mode_zeta
    elif only == "freeplay":
        keep.freeplay_deg = nz.freeplay_deg
    elif only == "latency":
        keep.latency_samples = nz.latency_samples
    elif only == "jitter":
        keep.jitter_frac = nz.jitter_frac
    elif only == "asbuilt":
        keep.mass_scale, keep.inertia_scale, keep.spring_scale = nz.mass_scale, nz.inertia_scale, nz.spring_scale
    elif only != "none":
        raise ValueError(f"--only: one of {NUISANCES}, asbuilt or none, not {only}")
    return keep


def as_built(w: Wing, nz: Nuisance) -> Wing:
    """The wing ``w`` as built: its panels' mass and inertia and its
    springs' torque (preload and stiffness) times the case's factors (the
    drawing's file, ``w.toml``, is the drawn wing's)."""
    if not nz.mass_scale:
        return w
    panels = [dataclasses.replace(p, mass_kg=p.mass_kg * a, inertia_kgm2=p.inertia_kgm2 * b) for p, a, b in zip(w.panels, nz.mass_scale, nz.inertia_scale)]
    joints = [dataclasses.replace(j, preload_nm=j.preload_nm * c, stiffness_nm_per_rad=j.stiffness_nm_per_rad * c) for j, c in zip(w.joints, nz.spring_scale)]
    return dataclasses.replace(w, panels=panels, joints=joints)


def draw_hidden(rng: np.random.Generator, kind: str, n: int) -> Hidden:
    """One effect of ``kind`` at a uniform joint, its value log-uniform over
    tests/src/hidden_effect.rs's range."""

    def u(lo: float, hi: float) -> float:
        return float(lo * (hi / lo) ** float(rng.uniform()))

    j = int(rng.integers(1, n + 1))
    if kind == "coulomb_friction":
        return Hidden(kind, j, u(0.05, 1.0))
    if kind == "viscous_damping":
        return Hidden(kind, j, u(0.05, 1.5))
    if kind == "spring_softening":
        return Hidden(kind, j, u(0.05, 0.35))
    return Hidden()


def campaign_wings(seed: int, rng: np.random.Generator) -> List[Wing]:
    """Seeds ≡ 0 (mod 3): seed 000's cases 1 and 3; the others random wings."""
    if seed % 3 == 0:
        return [wing_from_toml(os.path.join(ROOT, "data", "mechanisms", f"seed000_case{c}.toml")) for c in (1, 3)]
    return random_pair(rng, seed)


def generate(out: str, seed: int, only: Optional[str], as_built_too: bool = False) -> Dict[str, Any]:
    """Writes the campaign of ``seed`` under ``out/case<seed>`` and returns its truth."""
    rng = np.random.default_rng(seed)
    built_rng = np.random.default_rng([seed, 1])
    for _ in range(MAX_REDRAWS):
        wings = campaign_wings(seed, rng)
        n = len(wings[0].joints)
        nz = draw_nuisance(rng, n, only, built_rng, as_built_too)
        built = [as_built(w, nz) for w in wings]
        plain = [simulate(w, nz, Hidden()) for w in built]
        # A wing the nuisances swing past a turn is not a deployment (and
        # outside the run format's range): drawn again.
        if all(float(np.max(np.abs(tr.enc_deg), initial=0.0)) <= MAX_ANGLE_DEG for tr in plain):
            break
    kind = KINDS[seed % len(KINDS)]
    hidden, moved = Hidden(), 0.0
    floor = tolerance_floor(built, nz, plain) if kind != "none" else 0.0
    for attempt in range(12):
        if kind == "none":
            break
        hidden = draw_hidden(rng, kind, n)
        traces = [simulate(w, nz, hidden) for w in built]
        moved = effect_rms(plain, traces)
        if moved >= max(MIN_EFFECT_RMS_DEG, floor):
            break
    else:
        hidden, moved = Hidden(), 0.0
    if hidden.kind == "none":
        traces = plain
    d = os.path.join(out, f"case{seed:04d}")
    os.makedirs(d, exist_ok=True)
    files = []
    for w, tr in zip(wings, traces):
        mech = os.path.join(d, f"{w.name}.toml")
        with open(mech, "w", encoding="utf-8") as f:
            f.write(mechanism_toml(w))
        write_csv(os.path.join(d, f"{w.name}.csv"), w, sample(w, tr, nz, rng), f"MuJoCo {mujoco.__version__}, outside_engine.py seed {seed}")
        files.append(w.name)
    truth = {
        "seed": seed,
        "only": only,
        "runs": files,
        "effects": [] if hidden.kind == "none" else [{"name": hidden.kind, "joint": hidden.joint, "value": hidden.value, "unit": UNITS[hidden.kind]}],
        "effect_rms_deg": moved,
        "tolerance_floor_deg": floor,
        "nuisance": dataclasses.asdict(nz),
        "nuisance_rms_deg": effect_rms([simulate(w, Nuisance(), hidden) for w in wings], traces),
        "latch_s": [[None if math.isnan(x) else x for x in tr.latch_s] for tr in traces],
    }
    with open(os.path.join(d, "truth.json"), "w", encoding="utf-8") as f:
        json.dump(truth, f, indent=2)
    return truth


def spring_at_edge(w: Wing, joint: int, sign: float) -> Wing:
    """The wing ``w`` with joint ``joint``'s (0-based) spring torque at the
    ``sign`` edge of its declared band (``SPRING_TOLERANCE_PCT``)."""
    scale = 1.0 + sign * SPRING_TOLERANCE_PCT / 100.0
    joints = list(w.joints)
    j = joints[joint]
    joints[joint] = dataclasses.replace(j, preload_nm=j.preload_nm * scale, stiffness_nm_per_rad=j.stiffness_nm_per_rad * scale)
    return dataclasses.replace(w, joints=joints)


def tolerance_floor(built: List[Wing], nz: Nuisance, plain: List[Trace]) -> float:
    """How far the drawing's spring tolerances move the campaign's runs
    [deg RMS]: each joint's spring at the worse edge of its declared band
    (in both runs: one wing, one spring), the joints' moves summed in
    quadrature. A hidden effect that moves the runs by less is one the wing
    as drawn could make within its tolerances, and is drawn again, as one
    under ``MIN_EFFECT_RMS_DEG`` is for the noise."""
    moves = []
    for j in range(len(built[0].joints)):
        moves.append(max(effect_rms(plain, [simulate(spring_at_edge(w, j, s), nz, Hidden()) for w in built]) for s in (-1.0, 1.0)))
    return math.sqrt(sum(x * x for x in moves))


def effect_rms(a: List[Trace], b: List[Trace]) -> float:
    """RMS [deg] of the encoder-angle difference of two runs' traces over their common length."""
    sq, count = 0.0, 0
    for x, y in zip(a, b):
        k = min(len(x.t_s), len(y.t_s))
        diff = x.enc_deg[:k] - y.enc_deg[:k]
        sq += float(np.sum(diff**2))
        count += diff.size
    return math.sqrt(sq / max(count, 1))


# ---------------------------------------------------------------- scoring


def classify(truth: Dict[str, Any], effects: List[Dict[str, Any]]) -> str:
    """``right``: the hidden effect (if any) at its joint within ``REL_TOL``
    and nothing else claimed (``unexplained`` and ``discrepancy`` are not
    claims; a torque table is); ``honest``: not right, the answer says
    ``unexplained`` and claims nothing false; ``hedged``: a false claim
    beside ``unexplained``; ``wrong``: anything else (a confident wrong answer)."""
    want = truth["effects"]
    claims = [e for e in effects if e["name"] not in ("unexplained", "discrepancy")]
    said_unexplained = any(e["name"] in ("unexplained",) for e in effects)

    def matches(c: Dict[str, Any], t: Dict[str, Any]) -> bool:
        return bool(c["name"] == t["name"] and c.get("joint") == t["joint"]) and abs(c.get("value", math.inf) - t["value"]) <= REL_TOL * abs(t["value"])

    def true_claim(c: Dict[str, Any]) -> bool:
        return any(c["name"] == t["name"] and c.get("joint") == t["joint"] for t in want)

    if len(claims) == len(want) and all(any(matches(c, t) for c in claims) for t in want):
        return "right"
    false = [c for c in claims if not true_claim(c)]
    if said_unexplained:
        return "hedged" if false else "honest"
    return "wrong"


def score(out: str, exe: str, reuse: bool = False, seeds: Optional[range] = None) -> int:
    """Diagnoses every campaign of ``out`` and prints the counts; with
    ``reuse``, a campaign that already has its ``diagnosis.json`` is
    scored from it (its wall time from ``diagnosis.wall``, when there)."""
    cases = sorted(c for c in os.listdir(out) if c.startswith("case"))
    if seeds is not None:
        cases = [f"case{s:04d}" for s in seeds]
    counts: Dict[str, int] = {"right": 0, "honest": 0, "hedged": 0, "wrong": 0, "refused": 0}
    walls = []
    for c in cases:
        d = os.path.join(out, c)
        truth = json.load(open(os.path.join(d, "truth.json"), encoding="utf-8"))
        cmd = [exe, "diagnose"]
        for r in truth["runs"]:
            cmd += ["--mechanism", os.path.join(d, f"{r}.toml")]
        cmd += ["--json", os.path.join(d, "diagnosis.json")] + [os.path.join(d, f"{r}.csv") for r in truth["runs"]]
        done = os.path.join(d, "diagnosis.json")
        if reuse and os.path.exists(done):
            # A diagnosis of an earlier run of this command on this directory (--keep).
            p = subprocess.CompletedProcess(cmd, 0, "", "")
            wall_file = os.path.join(d, "diagnosis.wall")
            wall = float(open(wall_file).read()) if os.path.exists(wall_file) else math.nan
        else:
            start = time.perf_counter()
            p = subprocess.run(cmd, capture_output=True, text=True)
            wall = time.perf_counter() - start
            if p.returncode == 0:
                with open(os.path.join(d, "diagnosis.wall"), "w", encoding="utf-8") as f:
                    f.write(f"{wall}\n")
        if not math.isnan(wall):
            walls.append(wall)
        if p.returncode not in (0,) or not os.path.exists(done):
            # The diagnosis refused the campaign (e.g. an angle beyond the
            # format's ±720°: a generator fault, not an answer).
            verdict, found = "refused", [{"name": f"exit {p.returncode}: {p.stderr.strip()[-200:]}"}]
        else:
            found = json.load(open(os.path.join(d, "diagnosis.json"), encoding="utf-8"))["effects"]
            verdict = classify(truth, found)
        counts[verdict] += 1
        said = ", ".join(f"{e['name']}" + (f"@{e['joint']}" if e.get("joint") else "") + (f" {e['value']:.3g}" if isinstance(e.get("value"), (int, float)) else "") for e in found) or "nothing"
        hid = ", ".join(f"{e['name']}@{e['joint']} {e['value']:.3g}" for e in truth["effects"]) or "none"
        nz = truth["nuisance"]
        print(
            f"{c}: hidden {hid} (moves {truth['effect_rms_deg']:.2f} deg; nuisances {truth['nuisance_rms_deg']:.2f} deg, "
            f"mode {nz['mode_hz']:.1f} Hz, play {max(nz['freeplay_deg'], default=0):.2f} deg, "
            f"latency {nz['latency_samples']:.2f}, jitter {100 * nz['jitter_frac']:.1f} %) -> {said}: {verdict} ({'diagnosed earlier' if math.isnan(wall) else f'{wall:.1f} s'})"
        )
        sys.stdout.flush()
    total = len(cases)
    print()
    print(f"campaigns: {total} ({out}), MuJoCo {mujoco.__version__}")
    for k in counts:
        print(f"{k}: {counts[k]} of {total} ({100.0 * counts[k] / max(total, 1):.0f} %)")
    if walls:
        print(
            f"diagnose wall time over {len(walls)} campaigns: median {float(np.median(walls)):.1f} s, "
            f"max {max(walls):.1f} s (load average {os.getloadavg()[0]:.1f} at the end, 2 cores)"
        )
    return 0


def default_exe() -> str:
    """The release binary of this checkout (``DEPLOYWATCH`` overrides it)."""
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.environ.get("DEPLOYWATCH", os.path.join(target, "release", "deploywatch"))


def main(argv: List[str]) -> int:
    """``generate DIR N [FIRST_SEED] [--only NUISANCE]``, ``score DIR
    [DEPLOYWATCH]``, ``campaigns N [FIRST_SEED] [--only NUISANCE]``
    (both, in a temporary directory) or ``ablation N [FIRST_SEED [STEP]]``
    (each nuisance alone, and none, on the same N seeds, STEP apart)."""
    only, keep = None, None
    as_built_too = "--as-built" in argv
    argv = [a for a in argv if a != "--as-built"]
    if "--keep" in argv:
        i = argv.index("--keep")
        keep = argv[i + 1]
        argv = argv[:i] + argv[i + 2 :]
    if "--only" in argv:
        i = argv.index("--only")
        only = argv[i + 1]
        argv = argv[:i] + argv[i + 2 :]
    if len(argv) >= 3 and argv[0] == "generate":
        out, count = argv[1], int(argv[2])
        first = int(argv[3]) if len(argv) > 3 else 0
        os.makedirs(out, exist_ok=True)
        for s in range(first, first + count):
            t = generate(out, s, only, as_built_too)
            print(f"case{s:04d}: {t['effects']} moves {t['effect_rms_deg']:.2f} deg, nuisances {t['nuisance_rms_deg']:.2f} deg", flush=True)
        return 0
    if len(argv) >= 2 and argv[0] == "campaigns":
        # Generate and score in a fresh directory: the recorded command.
        count = int(argv[1])
        first = int(argv[2]) if len(argv) > 2 else 0
        if keep is not None:
            # Resumable: campaigns and diagnoses already in KEEP are kept.
            os.makedirs(keep, exist_ok=True)
            for s in range(first, first + count):
                if not os.path.exists(os.path.join(keep, f"case{s:04d}", "truth.json")):
                    generate(keep, s, only, as_built_too)
            print(f"nuisances: {only or 'all of ' + ', '.join(NUISANCES + (('asbuilt',) if as_built_too else ()))}; seeds {first}..{first + count - 1}")
            return score(keep, default_exe(), reuse=True, seeds=range(first, first + count))
        with tempfile.TemporaryDirectory(prefix="outside-engine-") as out:
            for s in range(first, first + count):
                generate(out, s, only, as_built_too)
            print(f"nuisances: {only or 'all of ' + ', '.join(NUISANCES + (('asbuilt',) if as_built_too else ()))}; seeds {first}..{first + count - 1}")
            return score(out, default_exe())
    if len(argv) >= 2 and argv[0] == "ablation":
        # Each nuisance alone on the same cases (and none): which breaks the answer.
        count = int(argv[1])
        first = int(argv[2]) if len(argv) > 2 else 0
        step = int(argv[3]) if len(argv) > 3 else 1
        seeds = range(first, first + count * step, step)
        for o in ("none",) + NUISANCES:
            with tempfile.TemporaryDirectory(prefix="outside-engine-") as out:
                for s in seeds:
                    generate(out, s, o)
                print(f"## only {o}; seeds {', '.join(map(str, seeds))}")
                score(out, default_exe())
                print()
        return 0
    if len(argv) >= 2 and argv[0] == "score":
        exe = argv[2] if len(argv) > 2 else default_exe()
        return score(argv[1], exe)
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
