"""A second opinion on the simulator: random ideal-latch wings run by
deploywatch and by MuJoCo (an engine the project did not write), compared
(docs/simulator.md, "A second opinion: MuJoCo").

The MuJoCo side is the reference physics of docs/spec/physics.md built from
MuJoCo's own parts: a planar chain of hinge bodies (gravity off, flight),
each hinge's linear spring as MuJoCo's joint stiffness (``k |phi|``) plus a
constant applied torque (the preload ``T0``, of the stowed side's sign: an
ideal latch stops a joint at 0, so the sign never changes while it is
free), viscous friction as MuJoCo's joint damping, the Coulomb friction
``T_C tanh(w / w_coul)`` (§4) as an applied torque set before each step
from the rate at its start and held over it (MuJoCo's passive-force
callback would evaluate it at every RK4 stage, at a Python call per
stage: this is the difference between the engines, docs/simulator.md),
and the latch of §5: at the crossing, located by
re-stepping to it, the plastic impulse on the free joints' mass matrix
(MuJoCo's ``mj_fullM``), then the joint held at 0 by a joint equality
switched on (``eq_active``).

    .venv/bin/python python/tests/second_opinion.py [WINGS] [FIRST_SEED]

prints one line per wing and the totals (the figures of docs/measured.md,
section ``second-opinion-mujoco``).
"""

from __future__ import annotations

import dataclasses
import os
import sys
import tempfile
import time
from typing import List, Optional

import mujoco
import numpy as np

import deploywatch

DT_S = 5e-4
"""MuJoCo's step [s] (RK4): the latch crossings are located inside it."""
SAMPLE_HZ = 200.0
"""Both runs are compared at this rate [Hz]."""
DURATION_S = 6.0
"""The runs' `[run] duration_s` [s]."""
MAX_PANELS = 8
"""The most panels a wing has: the mechanism format's limit
(`MAX_CHAIN_JOINTS` in host-sim/src/model/mechanism.rs); the MuJoCo side
takes any number."""
W_COUL = 0.01
"""The Coulomb law's regularisation ω_coul [rad/s] (physics.md §4)."""
RMS_DEG = 0.05
"""Target: RMS of the angle difference over the run [deg] (docs/simulator.md, "A second opinion: MuJoCo")."""
LATCH_S = 2e-3
"""Target: difference of each latch instant [s] (docs/simulator.md, "A second opinion: MuJoCo")."""


@dataclasses.dataclass
class Joint:
    """One joint: stowed angle [deg], linear spring per hinge (preload
    \\[N·m\\], stiffness \\[N·m/rad\\]) times ``count``, Coulomb \\[N·m\\]
    and viscous \\[N·m·s/rad\\] friction."""

    stowed_deg: float
    preload_nm: float
    stiffness_nm_per_rad: float
    count: int
    coulomb_nm: float
    viscous_nms: float


@dataclasses.dataclass
class Panel:
    """One panel: length \\[m\\], mass \\[kg\\], centre of mass from the
    inboard hinge \\[m\\], inertia about it \\[kg·m²\\]."""

    length_m: float
    mass_kg: float
    com_m: float
    inertia_kgm2: float


@dataclasses.dataclass
class Wing:
    """A random ideal-latch wing and the seed that drew it."""

    seed: int
    panels: List[Panel]
    joints: List[Joint]


def random_wing(seed: int) -> Wing:
    """2 to ``MAX_PANELS`` panels of random size, linear torsion springs, Coulomb and
    viscous friction, stowed angles of either sign up to 180°."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, MAX_PANELS + 1))
    panels, joints = [], []
    for _ in range(n):
        length = float(rng.uniform(0.3, 1.2))
        mass = float(rng.uniform(0.5, 5.0))
        panels.append(
            Panel(
                length_m=length,
                mass_kg=mass,
                com_m=length * float(rng.uniform(0.35, 0.65)),
                inertia_kgm2=mass * length**2 / 12.0 * float(rng.uniform(0.7, 1.3)),
            )
        )
        preload = float(rng.uniform(0.3, 2.5))
        joints.append(
            Joint(
                stowed_deg=float(rng.choice([-1.0, 1.0]) * rng.uniform(30.0, 180.0)),
                preload_nm=preload,
                stiffness_nm_per_rad=float(rng.uniform(0.05, 1.0)),
                count=int(rng.integers(1, 4)),
                coulomb_nm=float(rng.uniform(0.0, 0.3) * preload),
                viscous_nms=float(rng.uniform(0.0, 0.05)),
            )
        )
    return Wing(seed=seed, panels=panels, joints=joints)


def without_coulomb(w: Wing) -> Wing:
    """``w`` with its Coulomb friction taken out (in place)."""
    for j in w.joints:
        j.coulomb_nm = 0.0
    return w


def mechanism_toml(w: Wing) -> str:
    """The wing as a deploywatch mechanism file (docs/spec/formats.md)."""
    out = [f'name = "second-opinion-{w.seed}"', f'description = "random ideal-latch wing, seed {w.seed}"', ""]
    for p in w.panels:
        out += [
            "[[panel]]",
            f"length_m = {p.length_m!r}",
            f"mass_kg = {p.mass_kg!r}",
            f"com_m = {p.com_m!r}",
            f"inertia_kgm2 = {p.inertia_kgm2!r}",
            "",
        ]
    for j in w.joints:
        out += [
            "[[joint]]",
            f"stowed_deg = {j.stowed_deg!r}",
            f'spring = {{ kind = "linear", preload_nm = {j.preload_nm!r}, '
            f"stiffness_nm_per_rad = {j.stiffness_nm_per_rad!r}, count = {j.count} }}",
            f"friction = {{ coulomb_nm = {j.coulomb_nm!r}, viscous_nms = {j.viscous_nms!r} }}",
            "",
        ]
    out += ["[run]", f"duration_s = {DURATION_S}", f"sample_hz = {SAMPLE_HZ}", ""]
    return "\n".join(out)


def mjcf(w: Wing) -> str:
    """The wing as a MuJoCo model: nested bodies, one z hinge each, the
    spring's stiffness and the viscous friction as the joint's own
    ``stiffness``/``damping``, one (inactive) joint equality per joint."""
    body, close = [], []
    for i, (p, j) in enumerate(zip(w.panels, w.joints)):
        x = 0.0 if i == 0 else w.panels[i - 1].length_m
        inertia = p.inertia_kgm2
        body.append(
            f'<body name="p{i}" pos="{x!r} 0 0">'
            f'<joint name="j{i}" type="hinge" axis="0 0 1" '
            f'stiffness="{j.stiffness_nm_per_rad * j.count!r}" springref="0" damping="{j.viscous_nms!r}"/>'
            f'<inertial pos="{p.com_m!r} 0 0" mass="{p.mass_kg!r}" '
            f'diaginertia="{inertia!r} {inertia!r} {inertia!r}"/>'
        )
        close.append("</body>")
    eqs = "".join(
        f'<joint joint1="j{i}" polycoef="0 0 0 0 0" active="false" '
        f'solref="{2 * DT_S!r} 1" solimp="0.9999 0.9999 0.001 0.5 2"/>'
        for i in range(len(w.joints))
    )
    return (
        '<mujoco model="wing">'
        f'<option timestep="{DT_S!r}" gravity="0 0 0" integrator="RK4"/>'
        f"<worldbody>{''.join(body)}{''.join(close)}</worldbody>"
        f"<equality>{eqs}</equality>"
        "</mujoco>"
    )


@dataclasses.dataclass
class Run:
    """Sampled angles [deg] (n, joints) and latch instants [s] (NaN: not
    latched)."""

    phi_deg: np.ndarray
    latch_s: np.ndarray


def _latch_impulse(m: "mujoco.MjModel", d: "mujoco.MjData", free: np.ndarray, hit: List[int]) -> None:
    """physics.md §5: φ̇⁺ = φ̇⁻ − M⁻¹E (EᵀM⁻¹E)⁻¹ Eᵀ φ̇⁻ on the joints
    still free (``free``, those latching now among them), ``M`` MuJoCo's
    mass matrix at this instant; then the latched joints are at 0."""
    mujoco.mj_forward(m, d)
    full = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, full)
    idx = np.flatnonzero(free)
    mm = full[np.ix_(idx, idx)]
    v = d.qvel[idx].copy()
    e = np.zeros((len(idx), len(hit)))
    for c, j in enumerate(hit):
        e[list(idx).index(j), c] = 1.0
    minv_e = np.linalg.solve(mm, e)
    v -= minv_e @ np.linalg.solve(e.T @ minv_e, e.T @ v)
    d.qvel[idx] = v
    for j in hit:
        d.qpos[j] = 0.0
        d.qvel[j] = 0.0
        d.eq_active[j] = 1


def run_mujoco(w: Wing, end_s: float) -> Run:
    """The wing in MuJoCo from rest at its stowed angles until ``end_s``,
    sampled at ``SAMPLE_HZ``."""
    m = mujoco.MjModel.from_xml_string(mjcf(w))
    d = mujoco.MjData(m)
    n = len(w.joints)
    side = np.sign([j.stowed_deg for j in w.joints])
    d.qpos[:] = np.radians([j.stowed_deg for j in w.joints])
    # The preload T0 of each free joint, of the stowed side's sign.
    preload = np.array([-s * j.preload_nm * j.count for s, j in zip(side, w.joints)])
    coulomb = np.array([j.coulomb_nm for j in w.joints])
    free = np.ones(n, dtype=bool)
    latch = np.full(n, np.nan)
    per_sample = int(round(1.0 / (SAMPLE_HZ * DT_S)))
    samples = int(round(end_s * SAMPLE_HZ)) + 1
    phi = np.zeros((samples, n))
    phi[0] = np.degrees(d.qpos)
    for k in range(1, samples):
        for step in range(per_sample):
            t0 = (k - 1) * per_sample + step
            # Spring preload and Coulomb friction of the free joints, held over the step.
            d.qfrc_applied[:] = np.where(free, preload - coulomb * np.tanh(d.qvel / W_COUL), 0.0)
            _step(m, d, side, free, latch, t0 * DT_S)
        phi[k] = np.degrees(d.qpos)
    return Run(phi_deg=phi, latch_s=latch)


def _step(
    m: "mujoco.MjModel", d: "mujoco.MjData", side: np.ndarray, free: np.ndarray, latch: np.ndarray, t0: float
) -> None:
    """One step of ``DT_S``; a free joint that crosses 0 in it is latched at
    the crossing (the step re-taken to it by the secant rule on the
    joint's angle), and the step completed after the impulse."""
    qpos, qvel = d.qpos.copy(), d.qvel.copy()
    mujoco.mj_step(m, d)
    crossed = free & (side * d.qpos <= 0.0)
    if not crossed.any():
        return
    # The first crossing among them: secant iterations on the step length.
    lo, hi = 0.0, DT_S
    f_lo = qpos * side
    f_hi = d.qpos * side
    j = int(np.flatnonzero(crossed)[np.argmin([f_lo[i] / (f_lo[i] - f_hi[i]) for i in np.flatnonzero(crossed)])])
    for _ in range(40):
        h = lo + (hi - lo) * f_lo[j] / (f_lo[j] - f_hi[j])
        d.qpos[:], d.qvel[:] = qpos, qvel
        m.opt.timestep = h
        mujoco.mj_step(m, d)
        f = d.qpos * side
        if abs(f[j]) < 1e-12 or hi - lo < 1e-9:
            break
        if f[j] > 0:
            lo, f_lo = h, f
        else:
            hi, f_hi = h, f
    hit = [i for i in np.flatnonzero(free) if side[i] * d.qpos[i] <= 1e-9]
    _latch_impulse(m, d, free, hit)
    for i in hit:
        free[i] = False
        latch[i] = t0 + h
        d.qfrc_applied[i] = 0.0
    m.opt.timestep = DT_S - h
    if m.opt.timestep > 1e-12:
        _step_rest(m, d, side, free, latch, t0 + h)
    m.opt.timestep = DT_S


def _step_rest(
    m: "mujoco.MjModel", d: "mujoco.MjData", side: np.ndarray, free: np.ndarray, latch: np.ndarray, t0: float
) -> None:
    """The rest of a step after a latch (a second crossing in it is
    latched at the step's end: under ``DT_S`` late)."""
    mujoco.mj_step(m, d)
    hit = [i for i in np.flatnonzero(free) if side[i] * d.qpos[i] <= 0.0]
    if hit:
        _latch_impulse(m, d, free, hit)
        for i in hit:
            free[i] = False
            latch[i] = t0 + m.opt.timestep
            d.qfrc_applied[i] = 0.0


@dataclasses.dataclass
class Comparison:
    """One wing's figures: RMS angle difference [deg], worst latch-instant
    difference [s], the joints latched by one engine only."""

    seed: int
    joints: int
    rms_deg: float
    latch_diff_s: float
    latch_mismatch: List[int]

    @property
    def ok(self) -> bool:
        """Within both targets above."""
        return self.rms_deg <= RMS_DEG and self.latch_diff_s <= LATCH_S and not self.latch_mismatch

    def line(self) -> str:
        """One line of the report."""
        mis = f" latched by one engine only: joints {self.latch_mismatch}" if self.latch_mismatch else ""
        flag = "ok" if self.ok else "OUTSIDE"
        return (
            f"seed {self.seed:5d}  {self.joints} joints  RMS {self.rms_deg:.2e} deg  "
            f"latch {self.latch_diff_s * 1e3:.3f} ms  {flag}{mis}"
        )


def compare(seed: int) -> Comparison:
    """Runs the wing of ``seed`` in deploywatch and in MuJoCo and compares
    them over deploywatch's run (to its last sample)."""
    return compare_wing(random_wing(seed))


def compare_wing(w: Wing, workdir: Optional[str] = None) -> Comparison:
    """Runs ``w`` in deploywatch and in MuJoCo and compares them over
    deploywatch's run (to its last sample)."""
    seed = w.seed
    with tempfile.TemporaryDirectory(dir=workdir) as tmp:
        path = os.path.join(tmp, f"wing{seed}.toml")
        with open(path, "w", encoding="utf-8") as f:
            f.write(mechanism_toml(w))
        ours = deploywatch.simulate(path)
    end_s = float(ours.t_s[-1])
    theirs = run_mujoco(w, end_s)
    k = len(ours.t_s)
    diff = ours.phi_deg - theirs.phi_deg[:k]
    both = ~np.isnan(ours.latch_s) & ~np.isnan(theirs.latch_s)
    one = np.isnan(ours.latch_s) != np.isnan(theirs.latch_s)
    latch_diff = float(np.max(np.abs(ours.latch_s[both] - theirs.latch_s[both]), initial=0.0))
    return Comparison(
        seed=seed,
        joints=len(w.joints),
        rms_deg=float(np.sqrt(np.mean(diff**2))),
        latch_diff_s=latch_diff,
        latch_mismatch=[int(i) + 1 for i in np.flatnonzero(one)],
    )


def main(argv: List[str]) -> int:
    """Compares WINGS wings from FIRST_SEED on and prints the totals."""
    global DT_S
    wings = int(argv[0]) if argv else 100
    first = int(argv[1]) if len(argv) > 1 else 0
    start = time.perf_counter()
    results = [compare(s) for s in range(first, first + wings)]
    for r in results:
        print(r.line())
    ok = sum(r.ok for r in results)
    print()
    print(f"wings: {wings} (seeds {first}..{first + wings - 1}), 2-{MAX_PANELS} panels, ideal latches, linear springs")
    print(f"MuJoCo {mujoco.__version__}, RK4, step {DT_S:g} s; compared at {SAMPLE_HZ:g} Hz")
    print(f"within {RMS_DEG} deg RMS and {LATCH_S * 1e3:g} ms: {ok} of {wings} ({100.0 * ok / wings:.1f} %)")
    print(f"worst RMS: {max(r.rms_deg for r in results):.2e} deg")
    print(f"worst latch instant: {max(r.latch_diff_s for r in results) * 1e3:.3f} ms")
    print(f"joints latched by one engine only: {sum(len(r.latch_mismatch) for r in results)}")
    # The cause of the differences: the same wings without Coulomb friction.
    bare = [compare_wing(without_coulomb(random_wing(s))) for s in range(first, first + min(wings, 20))]
    print(f"the first {len(bare)} of them without Coulomb friction:")
    print(f"  worst RMS: {max(r.rms_deg for r in bare):.2e} deg")
    print(f"  worst latch instant: {max(r.latch_diff_s for r in bare) * 1e6:.3f} us")
    # The worst wing with MuJoCo's step halved twice: a difference of the
    # step (first order, the Coulomb torque held over it) falls with it.
    worst = max(results, key=lambda r: r.rms_deg)
    print(f"the worst wing (seed {worst.seed}) with MuJoCo's step halved:")
    step = DT_S
    for k in (1, 2, 4):
        DT_S = step / k
        r = compare(worst.seed)
        print(f"  step {DT_S:g} s: RMS {r.rms_deg:.2e} deg, latch instant {r.latch_diff_s * 1e3:.3f} ms")
    DT_S = step
    print(f"wall time: {time.perf_counter() - start:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
