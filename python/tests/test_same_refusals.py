"""One validator for every entry point: one
list of bad inputs, each run through the CLI binary and through Python.
The CLI exits 2; Python raises ``InputError`` (a ``MechanismError`` for the
file); the two messages are the same words, the CLI's flag (``--effect``,
``--vary``, ...) named as the Python argument (``effects[i]``, ``vary``,
...). Strings and the typed classes are refused alike.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_same_refusals.py -q
"""

import re
import subprocess

import pytest

import deploywatch as dw
from deploywatch import InputError, MechanismError

T01 = "data/mechanisms/seed001_T01.toml"
ONE = "data/mechanisms/reliability_one_panel.toml"
LATCH = "data/mechanisms/seed001_T01_physical_latch.toml"
VARY = "coulomb_friction:joint=1:normal(1,0.1)"

# (mechanism, bad --effect): the CLI's `simulate --effect` refusals
# (host-sim/tests/new_user_inputs.rs) and the new user's out-of-range values.
EFFECTS = [
    (T01, "coulomb_friction:joint=9:value=0.4"),
    (T01, "coulomb_friction:joint=0:value=0.4"),
    (T01, "coulomb_friction:joint=1:value=-5"),
    (T01, "coulomb_friction:joint=1:value=-1"),
    (T01, "spring_softening:joint=1:value=1"),
    (T01, "spring_softening:joint=2:value=1.5"),
    (T01, "harness_stiffness:joint=1:value=-0.5"),
    (T01, "coulomb_friction:value=0.4"),
    (T01, "air_drag:joint=1:value=0.1"),
    (T01, "gravity:joint=1:value=0.1"),
    (T01, "coulomb_friction:joint=1"),
    (T01, "coulomb_friction:joint=1:value=nan"),
    (T01, "plunger_weakening:joint=1:value=0.1"),
    (LATCH, "plunger_weakening:joint=4:value=0.1"),
    (T01, "magnet_weakening:joint=2:value=0.1"),
    (LATCH, "plunger_weakening:joint=1:value=1.5"),
]

# (option, value, Python argument, more CLI options): `reliability` on the
# one-panel mechanism (host-sim/tests/reliability_cli.rs).
RELIABILITY = [
    ("--vary", "coulomb_friction:joint=2:normal(1,0.1)", "vary", []),
    ("--vary", "coulomb_friction:joint=1:gauss(1,0.1)", "vary", []),
    ("--vary", "coulomb_friction:joint=1:normal(1,-0.1)", "vary", []),
    ("--vary", "panel_mass:joint=1", "vary", []),
    ("--fail", "time>20", "fail", ["--vary", VARY]),
    ("--fail", "landed", "fail", ["--vary", VARY]),
    ("--method", "form", "method", ["--vary", VARY]),
    ("--corr", "1,2,0.5", "corr", ["--vary", VARY]),
]


def cli_error(cli, args):
    """The CLI's message (stderr's `error:` line, clap's or the command's);
    asserts exit 2."""
    out = subprocess.run([cli, *args], capture_output=True, text=True)
    assert out.returncode == 2, (args, out.returncode, out.stderr)
    assert "panicked" not in out.stderr
    first = out.stderr.strip().splitlines()[0]
    assert first.startswith("error: "), out.stderr
    return first[len("error: ") :]


# The CLI's options and the Python arguments that take their values.
NAMES = {"--effect": "effects", "--vary": "vary", "--fail": "fail", "--corr": "corr", "--method": "method",
         "--from": "from_", "--samples": "samples"}


def as_python(message, flag, arg):
    """The CLI's message with its options named as Python names the
    arguments: clap's `invalid value 'V' for '--flag <X>': MSG` is
    `arg: MSG`; the command's `--flag ...` is `arg ...` (`flag` as `arg`,
    every other option as its argument)."""
    m = re.fullmatch(r"invalid value '.*' for '" + flag + r" <[^>]+>': (.*)", message, re.S)
    if m:
        # A message that names the argument itself (`method `form`: ...`)
        # is not prefixed with it again.
        said = m.group(1)
        message = said if said.startswith(arg + " ") else f"{arg}: {said}"
    else:
        message = re.sub(re.escape(flag) + r"\b", arg, message)
    return re.sub(r"--[a-z-]+\b", lambda f: NAMES.get(f.group(0), f.group(0)), message)


@pytest.mark.parametrize("mech,effect", EFFECTS)
def test_a_bad_effect_is_refused_with_the_clis_words(root, cli, tmp_path, mech, effect):
    said = cli_error(cli, ["simulate", str(root / mech), "--out", str(tmp_path / "r.csv"), "--effect", effect])
    assert not (tmp_path / "r.csv").exists()
    want = as_python(said, "--effect", "effects[0]")
    m = dw.Mechanism.from_toml(root / mech)
    for call in (
        lambda: dw.simulate(root / mech, [effect]),
        lambda: m.simulate(effects=[effect]),
        lambda: m.simulate(effects=[dw.Coulomb(joint=1, torque_nm=0.1), effect], sample_hz=100),
        lambda: m.check_effects([effect]),
    ):
        with pytest.raises(InputError) as e:
            call()
        got = str(e.value)
        if got.startswith("effects[1]"):
            got = "effects[0]" + got[len("effects[1]") :]
        assert got == want, (got, said)
        assert "--" not in got


@pytest.mark.parametrize(
    "typed,effect",
    [
        (dw.Coulomb(joint=9, torque_nm=0.4), "coulomb_friction:joint=9:value=0.4"),
        (dw.Coulomb(joint=0, torque_nm=0.4), "coulomb_friction:joint=0:value=0.4"),
        (dw.Coulomb(joint=1, torque_nm=-5), "coulomb_friction:joint=1:value=-5.0"),
        (dw.SpringSoftening(joint=1, fraction=1), "spring_softening:joint=1:value=1.0"),
        (dw.Harness(joint=1, nm_per_rad=-0.5), "harness_stiffness:joint=1:value=-0.5"),
        (dw.PlungerWeakening(joint=1, fraction=0.1), "plunger_weakening:joint=1:value=0.1"),
    ],
)
def test_a_bad_typed_effect_is_refused_as_its_string(root, cli, tmp_path, typed, effect):
    assert str(typed) == effect
    said = cli_error(cli, ["simulate", str(root / T01), "--out", str(tmp_path / "r.csv"), "--effect", effect])
    with pytest.raises(InputError) as e:
        dw.Mechanism.from_toml(root / T01).simulate(effects=[typed])
    assert str(e.value) == as_python(said, "--effect", "effects[0]")


@pytest.mark.parametrize("flag,value,arg,more", RELIABILITY)
def test_bad_reliability_arguments_are_refused_with_the_clis_words(root, cli, flag, value, arg, more):
    args = ["reliability", str(root / ONE), *more, flag, value]
    if flag != "--fail":
        args += ["--fail", "not_latched"]
    said = cli_error(cli, args)
    kw = {"vary": [VARY], "fail": ["not_latched"]}
    kw[arg] = value if arg == "method" else [value]
    with pytest.raises(InputError) as e:
        dw.reliability(dw.Mechanism.from_toml(root / ONE), **kw)  # type: ignore[arg-type]
    got = str(e.value)
    want = as_python(said, flag, arg)
    # Python names the item of a list (`vary[0]`) where clap names the
    # option; the words after it are the same.
    assert re.sub(r"^(\w+)\[0\]:", r"\1:", got) == want, (got, said)
    assert "--" not in got


def test_a_bad_mechanism_file_is_refused_with_the_clis_words(root, cli, tmp_path):
    text = (root / T01).read_text().replace("mass_kg", "mass_kilo", 1)
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    said = cli_error(cli, ["simulate", str(bad), "--out", str(tmp_path / "r.csv")])
    with pytest.raises(MechanismError) as e:
        dw.Mechanism.from_toml(bad)
    assert str(e.value) == said
    with pytest.raises(MechanismError) as e:
        dw.Mechanism.from_str(text, str(bad))
    assert str(e.value) == said


@pytest.mark.parametrize(
    "arg,typed",
    [
        ("vary", dw.Vary("coulomb_friction", 2, dw.Normal(1, 0.1))),
        ("fail", dw.LatchTime(above_s=20)),
    ],
)
def test_a_bad_typed_law_or_criterion_is_refused_as_its_string(root, cli, arg, typed):
    """What only the mechanism refuses (a joint it lacks, a time beyond its
    ``duration_s``) is refused by the command, with the CLI's words."""
    flag = "--" + arg
    args = ["reliability", str(root / ONE), flag, str(typed)]
    args += ["--fail", "not_latched"] if arg == "vary" else ["--vary", VARY]
    said = cli_error(cli, args)
    kw = {"vary": [VARY], "fail": [dw.NotLatched()]}
    kw[arg] = [typed]
    with pytest.raises(InputError) as e:
        dw.reliability(dw.Mechanism.from_toml(root / ONE), **kw)  # type: ignore[arg-type]
    got = re.sub(r"^(\w+)\[0\]:", r"\1:", str(e.value))
    assert got == as_python(said, flag, arg), (str(e.value), said)


@pytest.mark.parametrize(
    "arg,text,make,field",
    [
        ("vary", "panel_mass:joint=1:uniform(2.0,1.0)", lambda: dw.Vary("panel_mass", 1, dw.Uniform(2, 1)), "Uniform.hi"),
        ("vary", "coulomb_friction:joint=1:truncnormal(1.0,0.1,3.0,2.0)",
         lambda: dw.Vary("coulomb_friction", 1, dw.TruncNormal(1, 0.1, 3, 2)), "TruncNormal.hi"),
        ("vary", "coulomb_friction:joint=1:normal(1.0,-0.1)", lambda: dw.Normal(1, -0.1), "Normal.sd"),
        ("vary", "colomb_friction:joint=1:normal(1.0,0.1)",
         lambda: dw.Vary("colomb_friction", 1, dw.Normal(1, 0.1)), "Vary.name"),
        ("fail", "latch_rate>-1.0", lambda: dw.LatchRate(above_deg_s=-1), "LatchRate.above_deg_s"),
        ("fail", "time>0.0", lambda: dw.LatchTime(above_s=0), "LatchTime.above_s"),
    ],
)
def test_what_the_cli_refuses_on_any_mechanism_is_refused_where_it_is_written(root, cli, arg, text, make, field):
    """A law or criterion the CLI's parser refuses whatever the mechanism:
    the CLI refuses its string, and the typed object is refused on the
    line that makes it (``InputError`` naming the field), before any
    command; the string given to a command is refused with the CLI's words."""
    flag = "--" + arg
    args = ["reliability", str(root / ONE), flag, text]
    args += ["--fail", "not_latched"] if arg == "vary" else ["--vary", VARY]
    said = cli_error(cli, args)
    with pytest.raises(InputError, match=rf"^{re.escape(field)}: "):
        make()
    kw = {"vary": [VARY], "fail": ["not_latched"]}
    kw[arg] = [text]
    with pytest.raises(InputError) as e:
        dw.reliability(dw.Mechanism.from_toml(root / ONE), **kw)  # type: ignore[arg-type]
    got = re.sub(r"^(\w+)\[0\]:", r"\1:", str(e.value))
    assert got == as_python(said, flag, arg), (str(e.value), said)
