"""Every CLI command has its Python twin, with the CLI's numbers on the
bundled examples: ``margin``, ``identify``, ``diagnose`` and ``replay``
(host) run from Python and by the binary; their JSON (the status CSV for
replay) equal, apart from the wall-clock times they record.

    bash scripts/python-env.sh && .venv/bin/pytest python/tests/test_commands.py -q
"""

import csv
import json
import pickle
import re
import subprocess
import warnings

import numpy as np
import pytest

import deploywatch as dw
from deploywatch import InputError

T01 = "data/mechanisms/seed001_T01.toml"
T02 = "data/mechanisms/seed001_T02.toml"
EFT = ["data/examples/a_seed001_eft/seed001_T01.csv", "data/examples/a_seed001_eft/seed001_T02.csv"]
HARNESS = [
    "data/examples/c_seed001_friction_harness/seed001_T01.csv",
    "data/examples/c_seed001_friction_harness/seed001_T02.csv",
]
TIMES = {"wall_s", "seconds", "elapsed_s"}


def untimed(v):
    """A JSON value without the wall-clock times it records."""
    if isinstance(v, dict):
        return {k: untimed(x) for k, x in v.items() if k not in TIMES}
    if isinstance(v, list):
        return [untimed(x) for x in v]
    return v


def run_cli(cli, root, *args):
    out = subprocess.run([cli, *args], cwd=root, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return out


def test_margin_gives_the_clis_json(root, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    run_cli(cli, root, "margin", "--mechanism", T02, "--friction", "0.5,1.7,0.01", "--standard", "ecss-e-st-33-01c",
            "--json", str(tmp_path / "m.json"), "-q")
    want = json.loads((tmp_path / "m.json").read_text())
    got = dw.margin(T02, friction=[0.5, 1.7, 0.01], standard="ecss-e-st-33-01c")
    assert got.json == want
    rows = want["joints"]
    assert got.joints["torque_margin_pct"].tolist() == [r["torque_margin_pct"] for r in rows]
    # A parsed mechanism, read from its file, gives the same.
    assert dw.margin(dw.Mechanism.from_toml(T02), friction=[0.5, 1.7, 0.01], standard="ecss-e-st-33-01c").json == want


def test_an_infinite_margin_is_inf_not_nan(root, cli, tmp_path, monkeypatch):
    """A joint with nothing resisting it has an infinite margin: the CLI's
    JSON writes it ``null`` (JSON has no infinity), and ``joints``, its
    ``table`` and its pandas view give ``inf``, never NaN; the finite
    margins beside it are the JSON's, and ``json`` stays the CLI's file."""
    monkeypatch.chdir(root)
    run_cli(cli, root, "margin", "--mechanism", T02, "--friction", "0.5,1.7,0", "--json", str(tmp_path / "m.json"), "-q")
    want = json.loads((tmp_path / "m.json").read_text())
    got = dw.margin(T02, friction=[0.5, 1.7, 0.0])
    assert got.json == want
    rows = want["joints"]
    assert [r["torque_margin_pct"] is None for r in rows] == [False, False, True]
    for key in ("torque_margin_pct", "energy_margin_pct"):
        col = got.joints[key]
        assert col[:2].tolist() == [r[key] for r in rows[:2]], key
        assert col[2] == np.inf, (key, col)
        np.testing.assert_array_equal(got.table("joints")[key], col)
        np.testing.assert_array_equal(got.to_pandas()[key].to_numpy(), col)
    # No friction at all (the bundled nominal mechanism): every margin inf.
    nominal = dw.margin(T01)
    assert np.isposinf(nominal.joints["torque_margin_pct"]).all()
    assert np.isposinf(nominal.joints["energy_margin_pct"]).all()
    # Ideal latches engage nothing: no latching margin, NaN (not a number,
    # not an infinite one).
    assert np.isnan(nominal.joints["latching_margin_pct"]).all()


def test_margin_with_a_reviewers_settings_gives_the_clis_json(root, cli, tmp_path, monkeypatch):
    """The settings a reviewer signs under NASA-STD-5017: the test row of
    factors, the springs' tolerance and end-of-life loss, the dynamic
    margin over a required deployment time, and the plot along the stroke."""
    monkeypatch.chdir(root)
    run_cli(cli, root, "margin", "--mechanism", T02, "--friction", "0.5,1.7,0.01", "--standard", "nasa-std-5017",
            "--data-source", "test", "--spring-tolerance", "5", "--end-of-life", "3", "--deploy-time", "10",
            "--json", str(tmp_path / "m.json"), "-q")
    want = json.loads((tmp_path / "m.json").read_text())
    got = dw.margin(T02, friction=[0.5, 1.7, 0.01], standard="nasa-std-5017", data_source="test",
                    spring_tolerance_pct=5, end_of_life_pct=3.0, deploy_time_s=10, plot=tmp_path / "m.png")
    assert got.json == want
    assert (tmp_path / "m.png").stat().st_size > 0
    # The dynamic margin is there, and moves with the time required.
    assert want["deploy_time_s"] == 10 and all(j["dynamic"] is not None for j in want["joints"])
    assert dw.margin(T02, friction=[0.5, 1.7, 0.01], standard="nasa-std-5017", data_source="test",
                     spring_tolerance_pct=5, end_of_life_pct=3.0, deploy_time_s=2).json != want
    with pytest.raises(dw.InputError, match="deploy_time_s"):
        dw.margin(T02, deploy_time_s="10")
    with pytest.raises(dw.InputError, match="data_source"):
        dw.margin(T02, data_source="guess")


def test_identify_gives_the_clis_json(root, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    run_cli(cli, root, "identify", "--mechanism", T01, "--mechanism", T02, *EFT, "--method", "direct",
            "--json", str(tmp_path / "eft.json"), "-q")
    want = json.loads((tmp_path / "eft.json").read_text())
    got = dw.identify(EFT, [T01, dw.Mechanism.from_toml(T02)], method="direct")
    assert untimed(got.json) == untimed(want)
    assert got.json["joints"][0]["coulomb_nm"] == pytest.approx(2.63, abs=1e-3)


def test_diagnose_gives_the_clis_json(root, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    run_cli(cli, root, "diagnose", "--mechanism", T01, "--mechanism", T02, "--json", str(tmp_path / "cli.json"),
            *HARNESS, "-q")
    want = json.loads((tmp_path / "cli.json").read_text())
    got = dw.diagnose(HARNESS, [T01, T02], json=tmp_path / "py.json")
    assert untimed(got.json) == untimed(want)
    assert (tmp_path / "py.md").exists() and got.report == str(tmp_path / "py.md")


def test_replay_gives_the_clis_status_stream(root, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(root)
    run_cli(cli, root, "replay", EFT[0], "--mechanism", T01, "--target", "host", "--out", str(tmp_path / "s.csv"), "-q")
    with open(tmp_path / "s.csv") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    got = dw.replay(EFT[0], T01)
    head = rows[0]
    assert set(got.columns) <= set(head) and "t_s" in got.columns
    for name, col in got.columns.items():
        k = head.index(name)
        want = np.array([np.nan if r[k] == "" else float(r[k]) for r in rows[1:]])
        np.testing.assert_array_equal(col, want, err_msg=name)


def test_replay_text_columns_are_those_the_format_gives_whatever_the_run(root, monkeypatch):
    """The status CSV's text columns (docs/monitor.md: those without a
    unit) are in ``states`` and the rest in ``columns``, on a run without a
    fault as on one with: ``faults1``, empty when no fault is raised, is
    text in both (a notebook's code reads one place for it)."""
    monkeypatch.chdir(root)
    doc = open("docs/monitor.md", encoding="utf-8").read()
    text = {f"{m.group(1)}{{}}{m.group(2)}" for m in re.finditer(r"^\| `(\w+)<j>(\w*)` \| — \|", doc, re.M)}
    assert len(text) == 5, text
    got = dw.replay(EFT[0], T01)
    joints = sum(1 for name in got.columns if re.fullmatch(r"phi\d+_deg", name))
    want = {t.format(j) for t in text for j in range(1, joints + 1)}
    assert set(got.states) == want
    assert all(x == "" for x in got.states["faults1"]), "a clean run: no fault raised"
    assert not set(got.columns) & want


def test_command_errors_name_the_python_arguments(root, monkeypatch):
    monkeypatch.chdir(root)
    with pytest.raises(InputError) as e:
        dw.margin(T02, friction=[0.5])
    assert str(e.value).startswith("friction has 1 values") and "--" not in str(e.value)
    with pytest.raises(InputError) as e:
        dw.margin(T02, standard="nasa-std-0")
    assert "standard" in str(e.value) and "--" not in str(e.value) and "possible values" in str(e.value)
    with pytest.raises(InputError) as e:
        dw.margin(T02, json="/no/such/folder/m.json")
    assert str(e.value).startswith("json") and "--" not in str(e.value)
    # A negative number is a value, not a flag: the message says what is
    # wrong with it.
    with pytest.raises(InputError) as e:
        dw.margin(T02, friction=[-1.0, 0.2, 0.3])
    assert str(e.value).startswith("friction") and "unexpected argument" not in str(e.value), str(e.value)
    with pytest.raises(InputError) as e:
        dw.diagnose(EFT[0], T01, json="/tmp/never.json", max_seconds=-1)
    assert str(e.value).startswith("max_seconds: expected a positive number"), str(e.value)
    # A value that starts with `-` is a value of its argument, never a flag
    # of the command.
    for call, name in [
        (lambda: dw.margin(T02, data_source="--version"), "data_source"),
        (lambda: dw.margin(T02, standard="-h"), "standard"),
        (lambda: dw.margin(T02, factors={"--help": 1.0}), "factors"),
        (lambda: dw.diagnose(EFT[0], T01, json="/tmp/never.json", max_effects=-1), "max_effects"),
    ]:
        with pytest.raises(InputError) as e:
            call()
        said = str(e.value)
        assert name in said and "unexpected argument" not in said, said


@pytest.mark.parametrize(
    "mech_path, run_path",
    [
        (T01, EFT[0]),
        ("data/mechanisms/wing6_ideal.toml", "data/examples/wing6/wing6_ideal.csv"),
    ],
)
def test_the_monitor_sample_by_sample_gives_replays_statuses(root, monkeypatch, mech_path, run_path):
    monkeypatch.chdir(root)
    mech = dw.Mechanism.from_toml(mech_path)
    status = dw.replay(run_path, mech)
    with open(run_path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    head, body = rows[0], rows[1:]
    n = len(mech.joints)
    monitor = dw.Monitor(mech)
    assert monitor.joints == n
    joints = range(1, n + 1)
    got = []
    for r in body:
        v = dict(zip(head, r))
        sample = dw.Sample(
            t_s=float(v["t_s"]),
            phi_deg=[float(v[f"phi{j}_deg"]) for j in joints],
            latch=[v[f"latch{j}"] == "1" for j in joints],
        )
        got.append(monitor.update(sample))
    assert len(got) == len(status.columns["t_s"])
    for j in range(n):
        for name, key in (("phi", "phi_deg"), ("coulomb", "coulomb_nm"), ("margin", "margin_pct")):
            col = f"{name}{j + 1}_{key.split('_', 1)[1]}"
            want = status.columns[col]
            have = np.array([getattr(s, key)[j] for s in got])
            # The monitor computes in f32: the same f32 values.
            np.testing.assert_array_equal(have.astype(np.float32), want.astype(np.float32), err_msg=col)
    # Ideal latches: the monitor follows no resolution, every joint resolved.
    assert all(s.resolution == ("Resolved",) * n for s in got)
    with pytest.raises(InputError, match=rf"^sample: expected {n} angles"):
        monitor.update(dw.Sample(t_s=0.0, phi_deg=[0.0], latch=[False]))


def test_a_panel_s_declared_tolerances_are_read(root):
    """``mass_tolerance_pct`` and ``inertia_tolerance_pct`` of a ``[[panel]]`` reach ``Panel``; 0 where none is declared."""
    text = (root / T01).read_text().replace("inertia_kgm2 = 0.27", "inertia_kgm2 = 0.27\nmass_tolerance_pct = 0.5\ninertia_tolerance_pct = 1", 1)
    mech = dw.Mechanism.from_str(text)
    assert [(p.mass_tolerance_pct, p.inertia_tolerance_pct) for p in mech.panels] == [(0.5, 1.0)] + [(0.0, 0.0)] * (len(mech.panels) - 1)
    with pytest.raises(dw.MechanismError, match="inertia_tolerance_pct"):
        dw.Mechanism.from_str(text.replace("inertia_tolerance_pct = 1", "inertia_tolerance_pct = 30"))


def test_a_joint_s_declared_free_play_is_read(root):
    """``free_play_deg`` of a ``[[joint]]`` reaches ``Joint.free_play_deg``; 0 where none is declared."""
    text = (root / T01).read_text().replace("stowed_deg = -90.0", "stowed_deg = -90.0\nfree_play_deg = 0.15", 1)
    mech = dw.Mechanism.from_str(text)
    assert [j.free_play_deg for j in mech.joints] == [0.15] + [0.0] * (len(mech.joints) - 1)
    with pytest.raises(dw.MechanismError, match="free_play_deg"):
        dw.Mechanism.from_str(text.replace("free_play_deg = 0.15", "free_play_deg = -1.0"))


def test_a_spring_s_declared_tolerance_is_read(root):
    """``spring_tolerance_pct`` of a ``[[joint]]`` reaches ``Joint.spring_tolerance_pct``; 0 where none is declared."""
    text = (root / T01).read_text().replace("stowed_deg = -90.0", "stowed_deg = -90.0\nspring_tolerance_pct = 2", 1)
    mech = dw.Mechanism.from_str(text)
    assert [j.spring_tolerance_pct for j in mech.joints] == [2.0] + [0.0] * (len(mech.joints) - 1)
    with pytest.raises(dw.MechanismError, match="spring_tolerance_pct"):
        dw.Mechanism.from_str(text.replace("spring_tolerance_pct = 2", "spring_tolerance_pct = 25"))


def test_the_monitor_refuses_a_latch_switch_read_as_text(root):
    # bool("0") is True: a switch read from a CSV as text would read closed.
    # Refused where the sample is made, before the monitor sees it.
    monitor = dw.Monitor(dw.Mechanism.from_toml(root / T01))
    with pytest.raises(InputError, match=r"^Sample\.latch\[0\]: expected one bool per switch"):
        monitor.update(dw.Sample(t_s=0.0, phi_deg=[-90.0, 180.0, -180.0], latch=["0", "0", "0"]))
    status = monitor.update(dw.Sample(t_s=0.0, phi_deg=[-90.0, 180.0, -180.0], latch=[False, False, False]))
    assert status.samples == 1


def test_the_commands_warnings_are_user_warnings(root, tmp_path, cli):
    """What the binary says on stderr as ``warning: …`` its Python twin
    raises as ``UserWarning``s, word for word, pointing at the caller's
    line: here a stowed angle typed in radians."""
    text = (root / T01).read_text()
    assert "stowed_deg = 180.0" in text
    m = tmp_path / "radians.toml"
    m.write_text(text.replace("stowed_deg = 180.0", "stowed_deg = 3.1416", 1))
    out = subprocess.run(
        [cli, "margin", "--mechanism", str(m), "--friction", "2.63,1.7,0.001", "--quiet", "--json",
         str(tmp_path / "cli.json")],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr
    said = [line[len("warning: ") :] for line in out.stderr.splitlines() if line.startswith("warning: ")]
    assert any("radians" in w for w in said), out.stderr
    with pytest.warns(UserWarning) as caught:
        dw.margin(m, friction=[2.63, 1.7, 0.001])
    assert [str(w.message) for w in caught] == said
    assert all(w.filename == __file__ for w in caught), [w.filename for w in caught]


def test_a_mechanism_read_warns_of_its_unlikely_values_as_the_cli_does(root, tmp_path, cli):
    """A mechanism read by the package warns of what ``deploywatch
    simulate`` warns of (here a curve spring in radians and a mass in
    grams), word for word, once per read, at the user's line: read from a
    file, from text, or by ``simulate`` given the file. A pickled copy (a
    Dask worker's) does not warn again."""
    text = (root / T01).read_text()
    spring = 'spring = { kind = "curve", unfold = [[0.0, 1.5], [0.7854, 1.2], [1.5708, 1.0]], count = 1 }'
    lines = text.splitlines()
    springs = [i for i, l in enumerate(lines) if l.startswith("spring = ")]
    assert len(springs) == 3, springs
    lines[springs[0]] = spring
    m = tmp_path / "unlikely.toml"
    m.write_text(("\n".join(lines) + "\n").replace("mass_kg = 3.5", "mass_kg = 3500.0", 1))
    out = subprocess.run(
        [cli, "simulate", str(m), "--out", str(tmp_path / "run.csv")], capture_output=True, text=True
    )
    said = [line[len("warning: ") :] for line in out.stderr.splitlines() if line.startswith("warning: ")]
    assert out.returncode == 0, out.stderr
    assert any("radians" in w and "joint[1].spring" in w for w in said), out.stderr
    assert any("grams" in w and "panel[1].mass_kg" in w for w in said), out.stderr
    for read in (
        lambda: dw.Mechanism.from_toml(m),
        lambda: dw.Mechanism.from_str(m.read_text(), str(m)),
        lambda: dw.simulate(m),
    ):
        with pytest.warns(UserWarning) as caught:
            read()
        assert [str(w.message) for w in caught] == said
        assert all(w.filename == __file__ for w in caught), [w.filename for w in caught]
    with pytest.warns(UserWarning):
        unlikely = dw.Mechanism.from_toml(m)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        copy = pickle.loads(pickle.dumps(unlikely))
    assert copy.toml == unlikely.toml


def test_a_mechanism_in_memory_is_named_as_the_user_knows_it(root, tmp_path, monkeypatch):
    """A ``Mechanism`` made from text has no file: the command is handed a
    temporary one, which is deleted when it returns. What the user is given
    back names the ``Mechanism`` as it names itself, or a file that exists
    and holds what was analysed: never the deleted path."""
    monkeypatch.chdir(root)
    text = open(T02, encoding="utf-8").read()
    mech = dw.Mechanism.from_str(text, "wing-in-notebook")
    # Returned JSON, no file kept: the Mechanism's own name.
    got = dw.margin(mech, friction=[0.5, 1.7, 0.01])
    assert got.json["mechanism_file"] == "wing-in-notebook"
    # JSON kept: the mechanism's text beside it, the file the JSON names.
    kept = dw.margin(mech, friction=[0.5, 1.7, 0.01], json=tmp_path / "m.json")
    named = kept.json["mechanism_file"]
    assert named == str(tmp_path / "m.mechanism0.toml")
    assert open(named, encoding="utf-8").read() == text
    assert json.loads((tmp_path / "m.json").read_text())["mechanism_file"] == named
    # The margins are those of the file itself.
    assert kept.joints["torque_margin_pct"].tolist() == dw.margin(T02, friction=[0.5, 1.7, 0.01]).joints[
        "torque_margin_pct"].tolist()
    # An error about the mechanism names it as the user does, and so does a
    # warning about it.
    with pytest.raises(dw.InputError) as e:
        dw.margin(mech, friction=[0.5])
    assert "wing-in-notebook has 3 joints" in str(e.value), str(e.value)
    with pytest.warns(UserWarning, match="in-radians:31: `joint\\[3\\].stowed_deg`"):
        radians = dw.Mechanism.from_str(text.replace("stowed_deg = -180.0", "stowed_deg = -3.14159"), "in-radians")
    with pytest.warns(UserWarning) as caught:
        dw.margin(radians, friction=[0.5, 1.7, 0.01])
    said = [str(w.message) for w in caught]
    assert any(w.startswith("in-radians:31: `joint[3].stowed_deg`") for w in said), said
    assert not any("mechanism0.toml" in w for w in said), said
    assert all(w.filename == __file__ for w in caught), [w.filename for w in caught]
    # A Mechanism whose file has changed since it was read is the text read.
    edited = tmp_path / "edited.toml"
    edited.write_text(text, encoding="utf-8")
    as_read = dw.Mechanism.from_toml(edited)
    edited.write_text(text + "\n# edited after it was read\n", encoding="utf-8")
    with pytest.raises(dw.InputError) as e:
        dw.margin(as_read, friction=[0.5])
    assert f"{edited} (as read; the file has changed since) has 3 joints" in str(e.value), str(e.value)
    # diagnose keeps its files: its report's next-step commands name the
    # mechanism written beside them, which exists.
    dw.diagnose(HARNESS, [dw.Mechanism.from_toml(T01), dw.Mechanism.from_str(text)], json=tmp_path / "d.json")
    report = (tmp_path / "d.md").read_text()
    assert str(tmp_path / "d.mechanism1.toml") in report
    assert (tmp_path / "d.mechanism1.toml").read_text() == text
    assert not (tmp_path / "d.mechanism0.toml").exists(), "T01 is read from its unchanged file"


def test_commands_in_threads_leave_stdout_as_they_found_it(root, monkeypatch):
    """Silent commands (``echo=False``) run from several threads at once,
    each releasing the GIL: fd 1 points where it did before, once they
    are done."""
    import concurrent.futures as cf
    import os

    monkeypatch.chdir(root)
    before = os.readlink("/proc/self/fd/1")

    def job(i):
        return dw.replay(EFT[0], T01) if i % 2 else dw.margin(T01, friction=[0.5, 0.2, 0.1])

    for _ in range(10):
        with cf.ThreadPoolExecutor(4) as ex:
            list(ex.map(job, range(8)))
        assert os.readlink("/proc/self/fd/1") == before


def test_switches_are_booleans_and_odd_file_names_reach_the_command(root, tmp_path, monkeypatch):
    """``flight="False"`` is refused, not run as True; a file whose name
    starts with ``-`` is read as a file, not as a flag; a mechanism that is
    not UTF-8 text is refused naming the argument and the file."""
    import shutil

    monkeypatch.chdir(root)
    rig = "data/mechanisms/seed001_T01_rig.toml"
    for call in (lambda: dw.margin(rig, flight="False"), lambda: dw.margin(rig, echo=1)):
        with pytest.raises(InputError, match=r"^(flight|echo): expected True or False"):
            call()
    shutil.copy(T01, tmp_path / "-T01.toml")
    shutil.copy(EFT[0], tmp_path / "-run.csv")
    monkeypatch.chdir(tmp_path)
    assert dw.margin("-T01.toml").json["joints"] == dw.margin(root / T01).json["joints"]
    assert dw.replay("-run.csv", "-T01.toml").columns.keys() == dw.replay(root / EFT[0], root / T01).columns.keys()
    (tmp_path / "latin1.toml").write_bytes((root / T01).read_bytes().replace(b"seed", "s\xe9ed".encode("latin-1"), 1))
    for call in (lambda: dw.Mechanism.from_toml("latin1.toml"), lambda: dw.simulate("latin1.toml")):
        with pytest.raises(InputError, match=r"latin1\.toml: byte \d+ \(0xe9\) is not UTF-8"):
            call()
