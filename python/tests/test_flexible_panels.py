"""Flexible panels (docs/spec/physics.md §12) against an engine deploywatch
did not write: the wings of python/examples/outside_engine.py with flexible
panels alone (its ``--only flex`` draws: the deployed wing's first mode at
4–15 Hz, 1–3 % damping), simulated by MuJoCo with each panel split at
0.15 of its length (not deploywatch's split at mid-span with each half
uniform), and by deploywatch with ``[flexible_panels]`` at the same mode
and damping ratio. The hinge angles agree within 0.02 deg RMS of the
engines' agreement on the same wing rigid (docs/simulator.md "A second
opinion: MuJoCo") and the latch instants within 5 ms, while the rigid
model misses the flexible wing by more on most wings: the bending is
what the model holds, not what it ignores. Asserted on the campaigns' random
wings (seeds not divisible by 3); on seed 000's wings (the others) the two
lumpings do not agree at the same mode and damping (0.06 deg at 11 Hz,
0.2 deg at 4.9 Hz, no better than the rigid model: printed, not asserted;
docs/simulator.md, "Flexible panels").

    .venv/bin/pytest python/tests/test_flexible_panels.py -q
"""

import os
import sys

import numpy as np

import deploywatch as dw

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples"))
import outside_engine as oe  # noqa: E402

RMS_DEG = 0.02
"""The engines' angles on a flexible wing agree within this RMS [deg] of
their agreement on the same wing rigid (MuJoCo holds a Coulomb torque over
each of its steps, docs/simulator.md: up to 0.05 deg on these wings)."""
LATCH_S = 5e-3
"""The engines' latch instants agree within this [s]."""
SEEDS = range(int(os.environ.get("FLEXIBLE_PANELS_SEEDS", "4")))
"""The outside engine's campaign seeds compared (two wings each)."""


def _pairs(seed):
    """Each wing of campaign ``seed`` with flexible panels alone: its
    mechanism TOML, the nuisance drawn, MuJoCo's trace of it, and of the
    same wing rigid."""
    rng = np.random.default_rng(seed)
    built_rng = np.random.default_rng([seed, 1])
    wings = oe.campaign_wings(seed, rng)
    nz = oe.draw_nuisance(rng, len(wings[0].joints), "flex", built_rng, False)
    return [(oe.mechanism_toml(w), nz, oe.simulate(w, nz, oe.Hidden()), oe.simulate(w, oe.Nuisance(), oe.Hidden())) for w in wings]


def _rms_against(traj, trace):
    """RMS [deg] of ``traj``'s hinge angles against MuJoCo's ``trace``
    (its encoder side, linearly interpolated at ``traj``'s samples) over
    the samples both runs have."""
    end = min(traj.t_s[-1], trace.t_s[-1])
    keep = traj.t_s <= end
    theirs = np.stack([np.interp(traj.t_s[keep], trace.t_s, trace.enc_deg[:, j]) for j in range(traj.joints)], axis=1)
    return float(np.sqrt(np.mean((traj.phi_deg[keep] - theirs) ** 2)))


def _latch_diff(traj, trace):
    ours, theirs = np.asarray(traj.latch_s), np.asarray(trace.latch_s)
    both = ~np.isnan(ours) & ~np.isnan(theirs)
    assert np.array_equal(np.isnan(ours), np.isnan(theirs)), (ours, theirs)
    return float(np.max(np.abs(ours[both] - theirs[both]), initial=0.0))


def test_flexible_wings_agree_with_mujoco():
    lines, worse = [], 0
    for seed in SEEDS:
        for toml, nz, trace, rigid_trace in _pairs(seed):
            flexible = toml + f"\n[flexible_panels]\nfirst_mode_hz = {nz.mode_hz!r}\ndamping_ratio = {nz.mode_zeta!r}\n"
            ours = dw.Mechanism.from_str(flexible, f"seed {seed}").simulate()
            rigid = dw.Mechanism.from_str(toml, f"seed {seed}").simulate()
            rms, rigid_rms = _rms_against(ours, trace), _rms_against(rigid, trace)
            engines = _rms_against(rigid, rigid_trace)
            latch = _latch_diff(ours, trace)
            lines.append(
                f"seed {seed}: mode {nz.mode_hz:.2f} Hz, {100 * nz.mode_zeta:.1f} %: "
                f"flexible {rms:.4f} deg, {1e3 * latch:.2f} ms; rigid model {rigid_rms:.4f} deg; "
                f"engines on the rigid wing {engines:.4f} deg"
            )
            if seed % 3 != 0:
                assert rms <= engines + RMS_DEG and latch <= LATCH_S, "\n".join(lines)
                worse += rigid_rms > rms
    print("\n".join(lines))
    # The rigid model misses the random flexible wings by more than the
    # flexible one on most of them (a stiff mode moves a run little).
    random_wings = 2 * sum(1 for s in SEEDS if s % 3 != 0)
    assert worse >= 0.75 * random_wings, "\n".join(lines)
