"""Every error path of the package: the class (the package's hierarchy,
also the built-in class a caller would catch), a message that names the
argument and what was expected, the Rust error's cause kept; pickling keeps
all of it (what a Dask worker does with an exception).

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_errors.py -q
"""

import errno
import math
import pickle

import numpy as np
import pytest

import deploywatch
from deploywatch import (
    DeploywatchError,
    EvaluatorError,
    InputError,
    MechanismError,
    SimulationError,
)

MECH = "data/mechanisms/reliability_one_panel.toml"
VARY = [
    "coulomb_friction:joint=1:normal(1.1,0.1)",
    "panel_inertia:joint=1:truncnormal(0.16,0.02,0.1,0.3)",
]
# A normal law of the inertia that reaches negative values: some draws
# cannot be simulated.
NEGATIVE = ["panel_inertia:joint=1:normal(0.16,0.2)"]


@pytest.fixture
def mech(root):
    return root / MECH


def test_the_hierarchy():
    assert issubclass(InputError, DeploywatchError) and issubclass(InputError, ValueError)
    assert issubclass(MechanismError, InputError)
    assert issubclass(SimulationError, DeploywatchError) and issubclass(SimulationError, RuntimeError)
    assert issubclass(EvaluatorError, DeploywatchError) and issubclass(EvaluatorError, RuntimeError)
    assert not issubclass(SimulationError, ValueError)


# ---- the mechanism file -------------------------------------------------


def test_a_mechanism_that_is_not_a_path(root):
    with pytest.raises(InputError, match=r"^mechanism: expected a file name .*got int"):
        deploywatch.simulate(42)  # type: ignore[arg-type]


def test_a_missing_file_is_the_same_error_in_every_function(tmp_path, root):
    """A file that does not exist: ``MissingFileError``, an ``InputError``
    naming the argument and a ``FileNotFoundError`` (``errno.ENOENT``,
    ``filename``), whichever function was given it; pickled whole."""
    absent = tmp_path / "absent.toml"
    t01 = root / "data/mechanisms/seed001_T01.toml"
    calls = {
        "mechanism": lambda: deploywatch.simulate(absent),
        "path": lambda: deploywatch.Mechanism.from_toml(absent),
        "mechanisms[0]": lambda: deploywatch.identify([root / "data/examples/a_seed001_eft/seed001_T01.csv"], [absent]),
        "runs[0]": lambda: deploywatch.identify([absent], [t01]),
        "from_": lambda: deploywatch.margin(t01, from_=absent),
        "run": lambda: deploywatch.replay(absent, t01),
    }
    for name, call in calls.items():
        with pytest.raises(deploywatch.MissingFileError) as e:
            call()
        err = e.value
        assert isinstance(err, InputError) and isinstance(err, FileNotFoundError), name
        assert str(err) == f"{name}: {absent}: no such file", str(err)
        assert err.errno == errno.ENOENT and err.filename == str(absent), name
        again = pickle.loads(pickle.dumps(err))
        assert type(again) is type(err) and str(again) == str(err) and again.filename == err.filename


def test_a_folder_where_a_file_is_meant(tmp_path, root):
    """A folder's name where a file's is meant: the ``MissingFileError`` of
    a missing file (an ``InputError`` and a ``FileNotFoundError``, with
    ``errno.EISDIR`` as ``open`` gives), naming the argument and the path
    and saying it is a folder; never ``open``'s raw ``IsADirectoryError``."""
    folder = tmp_path / "wing.toml"
    folder.mkdir()
    t01 = root / "data/mechanisms/seed001_T01.toml"
    calls = {
        "path": lambda: deploywatch.Mechanism.from_toml(folder),
        "mechanism": lambda: deploywatch.simulate(folder),
        "from_": lambda: deploywatch.margin(t01, from_=folder),
        "run": lambda: deploywatch.replay(folder, t01),
    }
    for name, call in calls.items():
        with pytest.raises(deploywatch.MissingFileError) as e:
            call()
        err = e.value
        assert isinstance(err, InputError) and isinstance(err, FileNotFoundError), name
        assert str(err) == f"{name}: {folder}: is a folder, not a file", str(err)
        assert err.errno == errno.EISDIR and err.filename == str(folder), name
        again = pickle.loads(pickle.dumps(err))
        assert type(again) is type(err) and str(again) == str(err)
        assert again.errno == errno.EISDIR and again.filename == err.filename
    # The folder given as text, and the current folder, alike.
    with pytest.raises(deploywatch.MissingFileError, match=r"^path: \.: is a folder, not a file$"):
        deploywatch.Mechanism.from_toml(".")


def test_a_mechanism_file_that_is_not_toml(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\n[joint\n')
    with pytest.raises(MechanismError, match=r"bad\.toml:2: invalid TOML") as e:
        deploywatch.simulate(bad)
    assert isinstance(e.value, ValueError)


def test_a_file_name_and_a_files_text_swapped(root, monkeypatch):
    """A file's name where its text is meant, and its text where its name
    is meant: each refused with what was given and the call that takes it,
    not parsed as TOML (``invalid TOML at column 5``) or looked up as a
    file of many lines; a name that is not there is still a missing file."""
    monkeypatch.chdir(root)
    text = (root / MECH).read_text(encoding="utf-8")
    for name in (MECH, root / MECH):
        with pytest.raises(InputError, match=r"^text: expected the TOML text.*Mechanism\.from_toml\(") as e:
            deploywatch.Mechanism.from_str(name)
        assert not isinstance(e.value, MechanismError)
    with pytest.raises(InputError, match=r"^path: expected a file name, got a file's text \('name = .*Mechanism\.from_str"):
        deploywatch.Mechanism.from_toml(text)
    with pytest.raises(InputError, match=r"^mechanism: expected a file name, got a file's text"):
        deploywatch.simulate(text)
    with pytest.raises(InputError, match=r"^mechanism: expected a file name, got a file's text"):
        deploywatch.margin(text)
    with pytest.raises(InputError, match=r"^path: expected a file name, got a file's text"):
        deploywatch.Mechanism.from_toml('name = "wing"')
    with pytest.raises(FileNotFoundError, match="no such file"):
        deploywatch.Mechanism.from_toml("runs/a=1/wing.toml")


def test_a_mechanism_file_with_a_wrong_key(root):
    # Valid TOML, not a mechanism: the file, the line, the keys expected.
    with pytest.raises(MechanismError, match=r"pyproject\.toml:1: unknown key `build-system`; expected one of"):
        deploywatch.reliability(root / "python/pyproject.toml", vary=VARY)


# ---- strings of the CLI's syntax ----------------------------------------


@pytest.mark.parametrize("arg", ["effects"])
def test_a_single_string_where_a_list_is_expected_simulate(mech, arg):
    with pytest.raises(InputError, match=r"^effects: expected a list of strings, e\.g\. \['coulomb"):
        deploywatch.simulate(mech, "coulomb_friction:joint=1:value=1.2")


@pytest.mark.parametrize("arg", ["vary", "fail", "corr"])
def test_a_single_string_where_a_list_is_expected(mech, arg):
    kwargs = {"vary": VARY, arg: "not_latched"}
    with pytest.raises(InputError, match=rf"^{arg}: expected a list of strings, e\.g\. \['not_latched'\]"):
        deploywatch.reliability(mech, **kwargs)


def test_a_list_holding_a_number(mech):
    with pytest.raises(InputError, match=r"^vary\[1\]: expected a string or Vary, got float 1\.5"):
        deploywatch.reliability(mech, vary=[VARY[0], 1.5])


@pytest.mark.parametrize(
    "make, pattern",
    [
        (lambda: deploywatch.Coulomb(joint="1", torque_nm=0.5), r"Coulomb\.joint: expected an integer, got str '1'"),
        (lambda: deploywatch.Coulomb(joint=1.0, torque_nm=0.5), r"Coulomb\.joint: expected an integer, got float"),
        (lambda: deploywatch.Coulomb(joint=True, torque_nm=0.5), r"Coulomb\.joint: expected an integer, got bool"),
        (lambda: deploywatch.Viscous(joint=1, nms_per_rad="0.2"), r"Viscous\.nms_per_rad: expected a number, got str"),
        (lambda: deploywatch.RigTilt(0.1, alpha_deg=None), r"RigTilt\.alpha_deg: expected a number, got NoneType"),
        (lambda: deploywatch.Normal(1.0, [0.1]), r"Normal\.sd: expected a number, got list"),
        (lambda: deploywatch.Vary("coulomb_friction", "2", deploywatch.Normal(1, 0.1)), r"Vary\.joint: expected an integer"),
        (lambda: deploywatch.LatchTime(above_s="3"), r"LatchTime\.above_s: expected a number"),
    ],
)
def test_a_typed_argument_of_the_wrong_type_is_refused_where_it_is_written(make, pattern):
    with pytest.raises(InputError, match=pattern):
        make()


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: deploywatch.Normal(1.0, -0.1), "Normal.sd: expected a positive finite number (a standard deviation), got -0.1"),
        (lambda: deploywatch.Normal(1.0, 0), "Normal.sd: expected a positive finite number (a standard deviation), got 0.0"),
        (lambda: deploywatch.Normal(math.inf, 0.1), "Normal.mean: expected a finite number, got inf"),
        (lambda: deploywatch.Normal(1.0, math.nan), "Normal.sd: expected a positive finite number (a standard deviation), got nan"),
        (lambda: deploywatch.LogNormal(0.0, 0.5), "LogNormal.median: expected a positive finite number, got 0.0"),
        (lambda: deploywatch.LogNormal(2.0, math.inf),
         "LogNormal.sigma_ln: expected a positive finite number (the standard deviation of ln x), got inf"),
        (lambda: deploywatch.Uniform(2, 1), "Uniform.hi: expected a number above lo = 2.0, got 1.0"),
        (lambda: deploywatch.Uniform(0, math.inf), "Uniform.hi: expected a finite number, got inf"),
        (lambda: deploywatch.TruncNormal(1, 0.1, 3, 2), "TruncNormal.hi: expected a number above lo = 3.0, got 2.0"),
        (lambda: deploywatch.TruncNormal(1, -1, 0, 2), "TruncNormal.sd: expected a positive finite number (a standard deviation), got -1.0"),
        (lambda: deploywatch.TruncNormal(1, 0.1, math.nan, 2),
         "TruncNormal.lo: expected a number below inf (-inf keeps no lower bound), got nan"),
        (lambda: deploywatch.Vary("coulomb_friction", 1, "normal(1,0.1)"),
         "Vary.law: expected a Normal, LogNormal, Uniform or TruncNormal, got str 'normal(1,0.1)'"),
        (lambda: deploywatch.Vary(3, 1, deploywatch.Normal(1, 0.1)), "Vary.name: expected a string, got int 3"),
        (lambda: deploywatch.Vary("coulomb_friction", 0, deploywatch.Normal(1, 0.1)),
         "Vary.joint: expected a joint number from 1 (None for a global effect), got 0"),
        (lambda: deploywatch.LatchRate(above_deg_s=-1), "LatchRate.above_deg_s: expected a positive finite rate [deg/s], got -1.0"),
        (lambda: deploywatch.LatchTime(above_s=math.inf), "LatchTime.above_s: expected a positive finite time [s], got inf"),
        (lambda: deploywatch.LatchTime(above_s=0), "LatchTime.above_s: expected a positive finite time [s], got 0.0"),
        (lambda: deploywatch.Sample(t_s="0.0", phi_deg=[0.0], latch=[False]), "Sample.t_s: expected a number, got str '0.0'"),
        (lambda: deploywatch.Sample(t_s=math.nan, phi_deg=[0.0], latch=[False]), "Sample.t_s: expected a finite time [s], got nan"),
        (lambda: deploywatch.Sample(t_s=0.0, phi_deg="90", latch=[False]),
         "Sample.phi_deg: expected a list of numbers, one per joint, got str '90'"),
        (lambda: deploywatch.Sample(t_s=0.0, phi_deg=[0.0, "1"], latch=[False, False]),
         "Sample.phi_deg[1]: expected a number, got str '1'"),
        (lambda: deploywatch.Sample(t_s=0.0, phi_deg=[-math.inf], latch=[False]),
         "Sample.phi_deg[0]: expected an angle [deg], finite or NaN for a missing reading, got -inf"),
        (lambda: deploywatch.Sample(t_s=0.0, phi_deg=[0.0], latch=[1]),
         "Sample.latch[0]: expected one bool per switch (True: closed), got int 1"),
        (lambda: deploywatch.Sample(t_s=0.0, phi_deg=[0.0, 1.0], latch=[False]),
         "Sample.latch: expected one switch per angle of phi_deg (2), got 1"),
    ],
)
def test_a_typed_argument_of_an_impossible_value_is_refused_where_it_is_written(make, message):
    """A law, a varied parameter, a criterion or a monitor's sample whose
    value no mechanism takes (a standard deviation at or below 0, bounds
    the wrong way round, a number that is not finite, a switch that is not
    a bool): an ``InputError`` on the line that makes it, naming the field,
    the value and what was expected, not an error inside a command later."""
    with pytest.raises(InputError) as e:
        make()
    assert str(e.value) == message


@pytest.mark.parametrize(
    "make, pattern",
    [
        # The --vary parser's words, naming the field they are about.
        (lambda: deploywatch.Vary("colomb_friction", 1, deploywatch.Normal(1, 0.1)),
         r"^Vary\.name: `colomb_friction:joint=1:normal\(1\.0,0\.1\)`: unknown effect `colomb_friction`: expected one of coulomb_friction"),
        (lambda: deploywatch.Vary("torque_table", 1, deploywatch.Normal(1, 0.1)),
         r"^Vary\.name: `torque_table:joint=1:normal\(1\.0,0\.1\)`: .*torque_table needs angle_deg"),
        (lambda: deploywatch.Vary("panel_mass", None, deploywatch.Uniform(1, 2)),
         r"^Vary\.joint: `panel_mass:uniform\(1\.0,2\.0\)`: panel_mass needs joint=J \(from 1\)$"),
        (lambda: deploywatch.Vary("air_drag", 1, deploywatch.Uniform(0, 1)),
         r"^Vary\.joint: `air_drag:joint=1:uniform\(0\.0,1\.0\)`: air_drag is global: it takes no joint"),
        (lambda: deploywatch.Vary("coulomb_friction", None, deploywatch.Normal(1, 0.1)),
         r"^Vary\.joint: `coulomb_friction:normal\(1\.0,0\.1\)`: coulomb_friction acts on a joint: give joint=J"),
    ],
)
def test_a_vary_of_an_unknown_target_is_refused_where_it_is_written(make, pattern):
    with pytest.raises(InputError, match=pattern):
        make()


def test_the_typed_laws_refuse_what_the_vary_parser_refuses(root):
    """The laws' own checks and the ``--vary`` parser the CLI uses (its
    ``Dist::check``) agree: each law refused where it is written is
    refused as a string by ``parameters`` too, and each law taken there."""
    mech = root / MECH
    laws = [
        (deploywatch.Normal, (1.0, 0.1)), (deploywatch.Normal, (1.0, 0.0)), (deploywatch.Normal, (1.0, -0.1)),
        (deploywatch.Normal, (math.inf, 0.1)), (deploywatch.Normal, (1.0, math.inf)), (deploywatch.Normal, (-1.0, 0.1)),
        (deploywatch.LogNormal, (2.0, 0.5)), (deploywatch.LogNormal, (0.0, 0.5)), (deploywatch.LogNormal, (-1.0, 0.5)),
        (deploywatch.LogNormal, (2.0, 0.0)), (deploywatch.LogNormal, (math.nan, 0.5)),
        (deploywatch.Uniform, (0.0, 1.0)), (deploywatch.Uniform, (1.0, 1.0)), (deploywatch.Uniform, (2.0, 1.0)),
        (deploywatch.Uniform, (-math.inf, 1.0)), (deploywatch.Uniform, (0.0, math.inf)),
        (deploywatch.TruncNormal, (1.0, 0.1, 0.5, 1.5)), (deploywatch.TruncNormal, (1.0, 0.1, 0.0, math.inf)),
        (deploywatch.TruncNormal, (1.0, 0.1, -math.inf, 2.0)), (deploywatch.TruncNormal, (1.0, 0.1, -math.inf, math.inf)),
        (deploywatch.TruncNormal, (1.0, 0.1, 2.0, 2.0)), (deploywatch.TruncNormal, (1.0, 0.1, math.inf, math.inf)),
        (deploywatch.TruncNormal, (1.0, 0.1, math.nan, 2.0)), (deploywatch.TruncNormal, (1.0, 0.1, 0.0, math.nan)),
        (deploywatch.TruncNormal, (1.0, 0.0, 0.0, 2.0)), (deploywatch.TruncNormal, (math.nan, 0.1, 0.0, 2.0)),
    ]
    for cls, args in laws:
        text = f"air_drag:{cls.__name__.lower()}({','.join(repr(float(a)) for a in args)})"
        try:
            deploywatch.parameters(mech, [text])
            parsed = True
        except InputError:
            parsed = False
        try:
            law = cls(*args)
            made = True
        except InputError:
            made = False
        assert made == parsed, (text, made, parsed)
        if made:
            assert str(deploywatch.Vary("air_drag", None, law)) == text


def test_typed_arguments_take_numpy_numbers_and_no_joint():
    assert str(deploywatch.Coulomb(joint=np.int64(2), torque_nm=np.float32(0.5))) == "coulomb_friction:joint=2:value=0.5"
    assert str(deploywatch.Vary("air_drag", None, deploywatch.Uniform(0, 1))) == "air_drag:uniform(0.0,1.0)"
    assert str(deploywatch.Vary("panel_mass", np.int64(1), deploywatch.TruncNormal(3.5, 0.2, 3, math.inf))) == (
        "panel_mass:joint=1:truncnormal(3.5,0.2,3.0,inf)"
    )
    # A missing reading is NaN; numpy's bools are switches; kept as tuples.
    s = deploywatch.Sample(t_s=np.float32(0.5), phi_deg=np.array([math.nan, 90.0]), latch=np.array([True, False]))
    assert s.t_s == 0.5 and math.isnan(s.phi_deg[0]) and s.phi_deg[1] == 90.0 and s.latch == (True, False)
    assert type(s.latch[0]) is bool


@pytest.mark.parametrize(
    "mechanisms, pattern",
    [
        ([], r"^mechanisms: expected at least one mechanism, got an empty list"),
        (None, r"^mechanisms: expected a mechanism .* got NoneType"),
        ({"a": 1}, r"^mechanisms: expected a mechanism .* got dict"),
    ],
)
def test_no_mechanism_for_the_runs(root, tmp_path, mechanisms, pattern):
    run = root / "data/examples/a_seed001_eft/seed001_T01.csv"
    with pytest.raises(InputError, match=pattern):
        deploywatch.identify(run, mechanisms)
    with pytest.raises(InputError, match=pattern):
        deploywatch.diagnose(run, mechanisms, json=tmp_path / "d.json")


def test_an_unknown_effect_lists_every_kind_the_syntax_reads(mech):
    with pytest.raises(InputError, match=r"quadratic_damping.*stribeck_friction|stribeck_friction.*quadratic_damping"):
        deploywatch.simulate(mech, ["nonsense:joint=1:value=1"])


def test_an_unknown_effect(mech):
    with pytest.raises(InputError, match=r"^effects\[1\]: unknown effect `nonsense`: expected one of coulomb_friction"):
        deploywatch.simulate(mech, ["coulomb_friction:joint=1:value=1.2", "nonsense:joint=1:value=1"])


def test_an_effect_on_a_joint_the_mechanism_lacks(mech):
    with pytest.raises(InputError, match=r"joint 7 does not exist \(the mechanism has only joint 1\)"):
        deploywatch.simulate(mech, ["coulomb_friction:joint=7:value=1"])


def test_a_bad_sample_rate(mech):
    with pytest.raises(InputError, match=r"^sample_hz: expected a positive finite number, got -5\.0"):
        deploywatch.simulate(mech, sample_hz=-5)


def test_an_unknown_law(mech):
    with pytest.raises(InputError, match=r"^vary\[0\]: .*unknown law `normul`: expected normal, lognormal"):
        deploywatch.parameters(mech, ["coulomb_friction:joint=1:normul(1,2)"])


def test_an_unknown_criterion(mech):
    with pytest.raises(InputError, match=r"^fail\[1\]: .*latched_late: expected not_latched, latch_rate>X"):
        deploywatch.simulate_batch(mech, VARY, [[1.0, 0.16]], fail=["not_latched", "latched_late"])


def test_a_time_criterion_beyond_the_run(mech):
    with pytest.raises(InputError, match=r"time>100: X must be below the mechanism's duration_s \(10 s\)"):
        deploywatch.simulate_batch(mech, VARY, [[1.0, 0.16]], fail=["time>100"])


def test_a_bad_correlation(mech):
    with pytest.raises(InputError, match=r"^corr\[0\]: .*expected I,J,RHO"):
        deploywatch.reliability(mech, vary=VARY, corr=["1,2,3"])


def test_no_parameter_to_vary(mech):
    with pytest.raises(InputError, match=r"^expected at least one vary, or a from_ effect with an interval$"):
        deploywatch.reliability(mech)


def test_a_from_file_that_is_not_identify_json(mech):
    with pytest.raises(InputError, match=r"^from_: not JSON"):
        deploywatch.reliability(mech, vary=VARY, from_=mech)


# ---- arrays: shape, dtype, values ---------------------------------------


def test_params_as_one_row_of_two_parameters(mech):
    with pytest.raises(InputError) as e:
        deploywatch.simulate_batch(mech, VARY, np.array([1.0, 0.16]))
    msg = str(e.value)
    assert msg.startswith("params: expected a 2-D array of real numbers of shape (n, 2)")
    assert "coulomb_friction:joint=1" in msg and "panel_inertia:joint=1" in msg
    assert "got shape (2,) (one point is [[..., ...]])" in msg


def test_params_with_a_column_too_many(mech):
    with pytest.raises(InputError, match=r"shape \(n, 2\).*got shape \(1, 3\)$"):
        deploywatch.simulate_batch(mech, VARY, np.zeros((1, 3)))


def test_params_of_a_3d_array(mech):
    with pytest.raises(InputError, match=r"got shape \(2, 2, 1\)$"):
        deploywatch.simulate_batch(mech, VARY, np.ones((2, 2, 1)))


@pytest.mark.parametrize(
    "params, dtype",
    [([["1.0", "0.16"]], "<U4"), (np.array([[1 + 0j, 0.16]]), "complex128"), ([[True, False]], "bool")],
)
def test_params_that_are_not_real_numbers(mech, params, dtype):
    with pytest.raises(InputError, match=rf"^params: expected a 2-D array of real numbers .* got an array of dtype {dtype}$"):
        deploywatch.simulate_batch(mech, VARY, params)


def test_params_with_rows_of_unequal_length(mech):
    with pytest.raises(InputError, match=r"^params: expected .*; got rows of unequal length or non-numbers"):
        deploywatch.simulate_batch(mech, VARY, [[1.0, 0.16], [1.0]])


def test_params_with_a_nan(mech):
    with pytest.raises(InputError, match=r"^params\[1, 0\] \(coulomb_friction:joint=1:normal\(1\.1,0\.1\)\): expected a finite number, got nan$"):
        deploywatch.simulate_batch(mech, VARY, [[1.0, 0.16], [np.nan, 0.16]])


def test_params_of_one_column_as_a_vector(mech):
    # One parameter: a 1-D array is its column (not an error).
    b = deploywatch.simulate_batch(mech, VARY[:1], np.array([1.0, 1.2]))
    assert b.g.shape == (2,)


# ---- settings -----------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, pattern",
    [
        ({"method": "foo"}, r"^method `foo`: expected auto, is, subset or mc$"),
        ({"method": "levels"}, r"^method `levels`: expected auto, is, subset or mc$"),
        ({"method": 3}, r'^method: expected "auto", "is", "subset" or "mc", got int$'),
        ({"samples": 0}, r"^samples: expected an integer of at least 1, got 0$"),
        ({"samples": 1.5}, r"^samples: expected an integer, got float 1\.5$"),
        ({"samples": True}, r"^samples: expected an integer, got bool True$"),
        ({"seed": -1}, r"^seed: expected an integer of at least 0 and at most 18446744073709551615, got -1$"),
        ({"seed": 2**64}, r"^seed: expected an integer of at least 0 and at most"),
        ({"target_cov": 0}, r"^target_cov: expected a positive finite number, got 0\.0$"),
        ({"target_cov": "0.1"}, r"^target_cov: expected a positive number, got str '0\.1'$"),
        ({"executor": object()}, r"^executor: expected a concurrent\.futures\.Executor or a dask\.distributed\.Client"),
        ({"executor": None, "method": "subset", "samples": 1001}, r"^subset: 1001 samples per level keep N·p0 = 100\.1 of each level \(p0 = 0\.1\)"),
    ],
)
def test_bad_settings(mech, kwargs, pattern):
    with pytest.raises(InputError, match=pattern):
        deploywatch.reliability(mech, vary=VARY, **kwargs)


class _Immediate:
    """An executor that runs each task at once, here."""

    def submit(self, fn, *args):
        from concurrent.futures import Future

        f = Future()
        try:
            f.set_result(fn(*args))
        except BaseException as e:  # noqa: BLE001 - handed to the caller
            f.set_exception(e)
        return f


@pytest.mark.parametrize("value", [0, -3])
def test_bad_chunk_and_workers(mech, value):
    for arg in ("chunk", "workers"):
        with pytest.raises(InputError, match=rf"^{arg}: expected an integer of at least 1, got {value}$"):
            deploywatch.reliability(mech, vary=VARY, executor=_Immediate(), **{arg: value})


# ---- failures of the work -----------------------------------------------


def test_a_deployment_that_cannot_be_simulated(mech):
    with pytest.raises(SimulationError) as e:
        deploywatch.simulate_batch(mech, NEGATIVE, np.array([[0.16], [-0.1]]))
    err = e.value
    assert isinstance(err, RuntimeError)
    why = (
        "panel_inertia at joint 1 would be -0.1 kg·m²: expected > 0 (as the mechanism file); "
        "a law that reaches there wants truncnormal(mean,sd,lo,hi) kept inside"
    )
    assert str(err) == f"the deployment at panel_inertia:joint=1 = -0.1 failed: {why}"
    # The Rust error's source, kept as the cause.
    assert err.causes == (why,)
    assert isinstance(err.__cause__, DeploywatchError)
    assert str(err.__cause__) == err.causes[0]


def test_a_reliability_run_that_meets_such_a_deployment(mech):
    with pytest.raises(SimulationError, match=r"^the deployment at panel_inertia:joint=1 = -[0-9.]+ failed"):
        deploywatch.reliability(mech, vary=NEGATIVE, samples=1000)


def test_a_sensor_effect_in_simulate_is_refused(mech):
    # simulate returns the motion; an encoder's offset moves no joint, so
    # it would be accepted and do nothing.
    with pytest.raises(InputError, match=r"^effects\[0\] encoder_offset.*acts on the encoder's reading"):
        deploywatch.simulate(mech, [deploywatch.EncoderOffset(joint=1, deg=2.0)])


def test_a_drawn_friction_that_would_drive_its_joint(mech):
    # The mechanism has no friction of its own: a draw of -5 N·m would push
    # the panel open. Refused with the value, as --effect refuses it.
    law = ["coulomb_friction:joint=1:normal(0.1,1.0)"]
    with pytest.raises(SimulationError, match=r"coulomb_friction at joint 1 would be -5 N·m"):
        deploywatch.simulate_batch(mech, law, [[0.2], [-5.0]])


def test_an_executor_that_answers_too_few_values(mech):
    class Short(_Immediate):
        def submit(self, fn, *args):
            f = super().submit(fn, *args)
            g = f.result()[:-1]
            f2 = type(f)()
            f2.set_result(g)
            return f2

    with pytest.raises(EvaluatorError, match=r"values for a batch of \d+ points"):
        deploywatch.reliability(mech, vary=VARY, samples=1000, executor=Short(), chunk=10**6)


def _answering(change):
    """An executor whose tasks' answers pass through `change`."""

    class Changed(_Immediate):
        def submit(self, fn, *args):
            f = super().submit(fn, *args)
            f2 = type(f)()
            f2.set_result(change(f.result()))
            return f2

    return Changed()


def test_an_executor_that_answers_too_few_margins_per_row(mech):
    # Two failure modes (not_latched, time>4 at joint 1): rows of one margin
    # are an unusable answer, not a shorter problem.
    pattern = r"^the evaluation of a batch failed: a row of 1 margins; expected one per failure mode \(2\)$"
    with pytest.raises(EvaluatorError, match=pattern):
        deploywatch.reliability(mech, vary=VARY, fail=["not_latched", "time>4"], method="mc",
                                samples=1000, executor=_answering(lambda m: m[:, :1]))


def test_an_executor_that_answers_nan_margins(mech):
    # A NaN margin is neither failed nor safe: counted as safe it would
    # lower p_fail without a word, so the answer is refused.
    pattern = r"^the evaluation of a batch failed: row 0 of the batch has a margin NaN"
    with pytest.raises(EvaluatorError, match=pattern):
        deploywatch.reliability(mech, vary=VARY, method="mc", samples=1000,
                                executor=_answering(lambda m: np.full_like(m, np.nan)))


def test_an_executor_that_answers_one_g_per_row(mech):
    # The former protocol (one limit state per row) is refused, with what
    # the answer should be.
    pattern = r"^the evaluation of a batch failed: the executor's answer: expected a list of rows of floats"
    with pytest.raises(EvaluatorError, match=pattern):
        deploywatch.reliability(mech, vary=VARY, samples=1000, executor=_answering(lambda m: m.min(axis=1)))


def test_an_executor_whose_task_fails_raises_that_error(mech):
    class Broken(Exception):
        pass

    class Failing:
        def submit(self, fn, *args):
            raise Broken("the cluster went away")

    with pytest.raises(Broken, match="^the cluster went away$"):
        deploywatch.reliability(mech, vary=VARY, samples=1000, executor=Failing())


def test_a_task_error_on_a_thread_pool_arrives_as_itself(mech):
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=2) as ex:
        with pytest.raises(SimulationError, match=r"^the deployment at panel_inertia:joint=1 = -"):
            deploywatch.reliability(mech, vary=NEGATIVE, samples=1000, executor=ex, chunk=50)


# ---- pickling (what crosses a process boundary) -------------------------


@pytest.mark.parametrize("cls", [DeploywatchError, InputError, MechanismError, SimulationError, EvaluatorError])
def test_every_error_pickles_with_its_message_and_cause(cls):
    from deploywatch._errors import _from_rust

    kinds = {InputError: "input", MechanismError: "mechanism", SimulationError: "simulation",
             EvaluatorError: "evaluator", DeploywatchError: "error"}
    err = _from_rust(kinds[cls], "what went wrong", ["why", "deeper"])
    back = pickle.loads(pickle.dumps(err))
    assert type(back) is cls and str(back) == "what went wrong" and back.causes == ("why", "deeper")
    assert str(back.__cause__) == "why" and str(back.__cause__.__cause__) == "deeper"
    assert back.__cause__.__cause__.__cause__ is None


def test_a_real_error_pickles(mech):
    with pytest.raises(SimulationError) as e:
        deploywatch.simulate_batch(mech, NEGATIVE, [[-0.1]])
    back = pickle.loads(pickle.dumps(e.value))
    assert type(back) is SimulationError
    assert str(back) == str(e.value) and back.causes == e.value.causes
    assert str(back.__cause__) == str(e.value.__cause__)


@pytest.mark.parametrize(
    "call, pattern",
    [
        (lambda t01, tmp: deploywatch.margin(t01, friction="0.5"), r"^friction: expected a list of numbers, one per joint, got str '0\.5'$"),
        (lambda t01, tmp: deploywatch.margin(t01, friction=[0.1, None, 0.1]), r"^friction\[1\]: expected a number, got NoneType None$"),
        (lambda t01, tmp: deploywatch.margin(t01, factors=[1, 2]), r"^factors: expected a mapping \{kind: value\}, got list \[1, 2\]$"),
        (lambda t01, tmp: deploywatch.margin(t01, factors={"friction": "2"}), r"^factors\['friction'\]: expected a number, got str '2'$"),
        (
            lambda t01, tmp: deploywatch.diagnose([], [t01], json=tmp / "d.json", max_seconds="10"),
            r"^max_seconds: expected a number, got str '10'$",
        ),
        (
            lambda t01, tmp: deploywatch.diagnose([], [t01], json=tmp / "d.json", max_effects=2.5),
            r"^max_effects: expected an integer, got float 2\.5$",
        ),
    ],
)
def test_a_command_argument_of_the_wrong_type_is_an_input_error(call, pattern, root, tmp_path):
    """The commands' keyword arguments of the wrong type: ``InputError``
    naming the argument and what was expected, not a ``ValueError`` of
    ``float()`` or an ``AttributeError``."""
    with pytest.raises(InputError, match=pattern):
        call(root / "data/mechanisms/seed001_T01.toml", tmp_path)
