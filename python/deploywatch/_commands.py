"""``diagnose``, ``identify``, ``margin`` and ``replay`` (host) from Python:
each runs the CLI's own command in this process (its parser, its checks,
its numbers; the GIL released), from keyword arguments, into a temporary
folder (or the ``json``/``out`` path given), and returns its JSON as a
typed result with numpy columns (``echo=True`` lets the command print
its table on stdout too). Errors: ``InputError`` where the binary
exits 2, ``DeploywatchError`` where it exits 1, each naming the Python
argument where the CLI names its flag."""

from __future__ import annotations

import csv as _csv
import json as _json
import math as _math
import os as _os
import re as _re
import signal as _signal
import sys as _sys
import tempfile as _tempfile
import threading as _threading
from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, TypeGuard, Union

import numpy as _np

from . import _native
from ._checks import _argument_path, _bool, _file_name, _real, _whole
from ._errors import InputError
from ._model import Mechanism, PathLike
from ._results import FloatArray, _pandas

MechanismLike = Union[PathLike, Mechanism]


def _path(name: str, value: Any) -> str:
    """A file to write, as the command line takes it (``_argument_path``)."""
    if not isinstance(value, (str, _os.PathLike)):
        raise InputError(f"{name}: expected a file name (str or pathlib.Path), got {type(value).__name__}")
    p = _os.fspath(value)
    if not isinstance(p, str):
        raise InputError(f"{name}: expected a file name as text, got {type(p).__name__}")
    return _argument_path(p)


def _existing(name: str, value: Any) -> str:
    """A file to read (``_checks._file_name``), as the command line takes
    it (``_argument_path``)."""
    return _argument_path(_file_name(name, value))


def _reals(name: str, value: Any) -> List[float]:
    """A list of real numbers (one per joint)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise InputError(f"{name}: expected a list of numbers, one per joint, got {type(value).__name__} {value!r}")
    return [_real(f"{name}[{i}]", v) for i, v in enumerate(value)]


def _paths(name: str, value: Any) -> List[str]:
    if isinstance(value, (str, _os.PathLike)):
        return [_existing(name, value)]
    try:
        items = list(value)
    except TypeError:
        raise InputError(f"{name}: expected file names, got {type(value).__name__}") from None
    if not items:
        raise InputError(f"{name}: expected at least one file name")
    return [_existing(f"{name}[{i}]", v) for i, v in enumerate(items)]


def _mechanism_file(name: str, value: Any, where: str, names: Dict[str, str]) -> str:
    """A mechanism's file: its own when it was read from one and is
    unchanged, else its text written to ``where`` and ``where`` entered in
    ``names`` with the name the user knows it by (its ``source``, marked
    when the file has changed since it was read)."""
    if isinstance(value, Mechanism):
        src = value.source
        changed = False
        if _os.path.isfile(src):
            with open(src, encoding="utf-8") as f:
                if f.read() == value.toml:
                    return _argument_path(src)
            changed = True
        try:
            with open(where, "w", encoding="utf-8") as f:
                f.write(value.toml)
        except OSError as e:
            raise InputError(f"{name}: its text cannot be written to {where}: {e.strerror}") from None
        names[where] = f"{src} (as read; the file has changed since)" if changed else src
        return where
    return _existing(name, value)


def _beside(out: str, i: int) -> str:
    """Where an in-memory mechanism is written when the command keeps its
    output at ``out``: beside it (``<stem>.mechanism<i>.toml``), so that
    the commands its report shows run as written."""
    return f"{_os.path.splitext(out)[0]}.mechanism{i}.toml"


#: The margins [%] of ``margin``'s JSON that JSON cannot always hold, each
#: with the two terms of the record it is made of: ``(driving / resisting
#: - 1) * 100``, infinite when nothing resists. The CLI writes such a
#: margin as ``null``; its terms, written beside it, give it back.
_MARGIN_TERMS: Dict[str, Tuple[str, str]] = {
    "torque_margin_pct": ("driving_torque_nm", "factored_resisting_torque_nm"),
    "energy_margin_pct": ("driving_energy_j", "factored_resisting_energy_j"),
}


def _margin_pct(driving: float, resisting: float) -> float:
    """``(driving / resisting - 1) * 100`` [%] as the CLI computes it
    (``design_margin::margin_pct``): ``+inf`` when ``resisting`` is 0 and
    ``driving`` above it, IEEE division otherwise."""
    if resisting == 0.0 and driving > 0.0:
        return _math.inf
    with _np.errstate(divide="ignore", invalid="ignore"):
        ratio = _np.float64(driving) / _np.float64(resisting)
    return float((ratio - 1.0) * 100.0)


def _number(x: Any) -> TypeGuard[float]:
    """A JSON number (not a bool)."""
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _columns(rows: Sequence[Mapping[str, Any]]) -> Dict[str, FloatArray]:
    """The numeric fields of a list of records as float64 columns. ``None``
    (how the CLI's JSON writes a value that is not finite) is NaN, but for
    a margin of ``_MARGIN_TERMS`` whose terms are in the record: the value
    they give, ``inf`` when nothing resists."""
    out: Dict[str, FloatArray] = {}
    if not rows:
        return out
    for key, v in rows[0].items():
        if isinstance(v, bool) or not isinstance(v, (int, float, type(None))):
            continue
        col = [r.get(key) for r in rows]
        if all(x is None or _number(x) for x in col):
            out[key] = _np.array([_np.nan if x is None else float(x) for x in col], dtype=_np.float64)
    for key, (driving, resisting) in _MARGIN_TERMS.items():
        if key not in out:
            continue
        for i, r in enumerate(rows):
            d, f = r.get(driving), r.get(resisting)
            if r.get(key) is None and _number(d) and _number(f):
                m = _margin_pct(float(d), float(f))
                # A null is a value that is not finite: terms that give a
                # finite one are not these (left NaN, as unknown).
                if not _math.isfinite(m):
                    out[key][i] = m
    return out


@dataclass(frozen=True)
class CommandResult:
    """A command's result: ``json``, the CLI's JSON as it wrote it (a dict;
    equal to the file the binary writes with the same arguments)."""

    json: Dict[str, Any]

    def table(self, key: str) -> Dict[str, FloatArray]:
        """The list of records under ``key`` as numpy columns (numbers
        only; NaN where the JSON has ``null``, but ``inf`` for a margin
        ``margin``'s JSON writes as ``null`` because nothing resists)."""
        rows = self.json.get(key)
        if not isinstance(rows, list):
            raise KeyError(f"{key}: not a list of records in this result (keys: {', '.join(self.json)})")
        return _columns([r for r in rows if isinstance(r, dict)])


@dataclass(frozen=True)
class Margins(CommandResult):
    """``deploywatch margin``: ``joints`` the per-joint table as numpy
    columns (``torque_margin_pct``, ``energy_margin_pct``, ...). A joint
    with nothing resisting it has an infinite margin: ``inf`` in
    ``joints`` (``json``, the CLI's JSON, writes it ``null``);
    ``latching_margin_pct`` is NaN for an ideal latch (nothing to
    engage, no latching margin)."""

    joints: Dict[str, FloatArray]

    def to_pandas(self) -> Any:
        """A ``pandas.DataFrame`` view of ``joints``, one row per joint."""
        return _pandas().DataFrame(self.joints)


@dataclass(frozen=True)
class Identification(CommandResult):
    """``deploywatch identify``: the JSON (the EFT per joint with its
    interval, as the CLI writes it)."""


@dataclass(frozen=True)
class Diagnosis(CommandResult):
    """``deploywatch diagnose``: the findings JSON; ``report`` the path of
    the Markdown report written beside it (with its plots)."""

    report: str


@dataclass(frozen=True)
class Replay:
    """``deploywatch replay --target host``: the monitor's status stream,
    one numpy column per numeric column of the status CSV the CLI writes
    (docs/monitor.md §1.1; NaN where it is empty), among them each
    prediction's ``confidence<j>`` [0..1] and ``time_to_latch<j>_s`` [s],
    and the text columns (latch state, prediction, faults) in
    ``states``."""

    columns: Dict[str, FloatArray]
    states: Dict[str, Tuple[str, ...]]

    def to_pandas(self) -> Any:
        """A ``pandas.DataFrame`` view indexed by ``t_s``: the numeric
        columns, then the text ones."""
        pd = _pandas()
        frame = pd.DataFrame({**self.columns, **{k: list(v) for k, v in self.states.items()}})
        return frame.set_index("t_s") if "t_s" in frame else frame


def _joined(args: List[str]) -> List[str]:
    """``--flag value`` as ``--flag=value`` where the value starts with
    ``-`` (a negative number), which the command line would take for a
    flag of its own."""
    out: List[str] = []
    for a in args:
        if out and out[-1].startswith("--") and "=" not in out[-1] and _negative(a):
            out[-1] = f"{out[-1]}={a}"
        else:
            out.append(a)
    return out


def _negative(text: str) -> bool:
    """A value that starts with ``-``: a negative number, or a list of
    numbers that starts with one (``-1,0.2``)."""
    if not text.startswith("-") or text.startswith("--"):
        return False
    try:
        float(text.split(",")[0].split("=")[-1])
    except ValueError:
        return False
    return True


#: The silenced stdout of the commands running now: how many, and the
#: descriptor of the stdout they silenced. The first to start points fd 1
#: at /dev/null and the last to end puts it back, so that commands run
#: from several threads at once (each releases the GIL) leave stdout as
#: they found it.
_silence_lock = _threading.Lock()
_silence: Dict[str, int] = {"count": 0, "saved": -1}


def _silence_stdout() -> None:
    with _silence_lock:
        if _silence["count"] == 0:
            _sys.stdout.flush()
            saved = _os.dup(1)
            null = _os.open(_os.devnull, _os.O_WRONLY)
            try:
                _os.dup2(null, 1)
            finally:
                _os.close(null)
            _silence["saved"] = saved
        _silence["count"] += 1


def _restore_stdout() -> None:
    with _silence_lock:
        _silence["count"] -= 1
        if _silence["count"] == 0:
            saved = _silence["saved"]
            _os.dup2(saved, 1)
            _os.close(saved)
            _silence["saved"] = -1


def _run(args: List[str], echo: bool, names: Mapping[str, str] = {}) -> None:
    """Runs the command; what it prints on stdout (its table, which the
    result holds too) is dropped unless ``echo``. The process's stdout is
    silenced while any such command runs (``_silence_stdout``): what other
    threads print then is lost, and so is the table of an ``echo=True``
    command that overlaps one. Its errors and warnings call each temporary
    file of ``names`` by the name the user knows it by
    (``_mechanism_file``)."""
    args = _joined(args)
    named = list(names.items())
    if _bool("echo", echo):
        _native.run_command(args, named)
        return
    _silence_stdout()
    try:
        _native.run_command(args, named)
    finally:
        _restore_stdout()


def _read_json(path: str) -> Dict[str, Any]:
    with open(path, encoding="utf-8") as f:
        out = _json.load(f)
    if not isinstance(out, dict):
        raise InputError(f"{path}: expected a JSON object")
    return out


def margin(
    mechanism: MechanismLike,
    friction: Optional[Sequence[float]] = None,
    from_: Optional[PathLike] = None,
    standard: str = "none",
    factors: Mapping[str, float] = {},
    flight: bool = False,
    json: Optional[PathLike] = None,
    echo: bool = False,
    data_source: str = "analysis",
    spring_tolerance_pct: float = 0.0,
    end_of_life_pct: float = 0.0,
    deploy_time_s: Optional[float] = None,
    plot: Optional[PathLike] = None,
) -> Margins:
    """``deploywatch margin`` (the options as keyword arguments: ``friction``
    [N·m] per joint, ``from_`` an ``identify``/``diagnose`` JSON,
    ``standard`` ``"none"``, ``"nasa-std-5017"``, ``"ecss-e-st-33-01c"`` or
    ``"aiaa-s-114"``, ``data_source`` the standard's row of factors
    (``"analysis"``, ``"test"``, ``"acceptance-extremes"``), ``factors``
    ``{kind: value}``, ``spring_tolerance_pct`` and ``end_of_life_pct`` the
    springs' torque below nominal [%], ``deploy_time_s`` the time required
    to complete each stroke [s] (the dynamic margin), ``flight``; ``json``
    keeps the file (and a mechanism given in memory beside it, as
    ``<stem>.mechanism0.toml``, the file it names), ``plot`` draws the
    static margin along the stroke as a PNG there)."""
    names: Dict[str, str] = {}
    with _tempfile.TemporaryDirectory() as tmp:
        out = _path("json", json) if json is not None else _os.path.join(tmp, "margin.json")
        if json is not None:
            mech = _mechanism_file("mechanism", mechanism, _beside(out, 0), {})
        else:
            mech = _mechanism_file("mechanism", mechanism, _os.path.join(tmp, "mechanism0.toml"), names)
        args = ["margin", "--mechanism", mech, "--quiet", "--json", out]
        if friction is not None:
            args += ["--friction", ",".join(repr(x) for x in _reals("friction", friction))]
        if from_ is not None:
            args += ["--from", _existing("from_", from_)]
        # `--flag=value`: a value starting with `-` is the value, not a flag.
        args.append(f"--standard={standard}")
        if not isinstance(factors, Mapping):
            raise InputError(f"factors: expected a mapping {{kind: value}}, got {type(factors).__name__} {factors!r}")
        for k, v in factors.items():
            args.append(f"--factor={k}={_real(f'factors[{k!r}]', v)!r}")
        args.append(f"--data-source={data_source}")
        args += ["--spring-tolerance", repr(_real("spring_tolerance_pct", spring_tolerance_pct))]
        args += ["--end-of-life", repr(_real("end_of_life_pct", end_of_life_pct))]
        if deploy_time_s is not None:
            args += ["--deploy-time", repr(_real("deploy_time_s", deploy_time_s))]
        if plot is not None:
            args += ["--plot", _path("plot", plot)]
        if _bool("flight", flight):
            args.append("--flight")
        _run(args, echo, names)
        doc = _read_json(out)
    # The one path the JSON holds: the mechanism's file, named as the user knows it.
    file = doc.get("mechanism_file")
    if isinstance(file, str):
        doc["mechanism_file"] = names.get(file, file)
    rows = doc.get("joints", [])
    return Margins(json=doc, joints=_columns(rows if isinstance(rows, list) else []))


def identify(
    runs: Union[PathLike, Sequence[PathLike]],
    mechanisms: Union[MechanismLike, Sequence[MechanismLike]],
    method: str = "direct",
    json: Optional[PathLike] = None,
    echo: bool = False,
) -> Identification:
    """``deploywatch identify`` of measured runs (CSV) on their mechanisms
    (``method`` ``"direct"`` or ``"rsm"``; ``json`` keeps the file, and a
    mechanism given in memory beside it as ``<stem>.mechanism<i>.toml``)."""
    with _tempfile.TemporaryDirectory() as tmp:
        out = _path("json", json) if json is not None else _os.path.join(tmp, "identify.json")
        args = ["identify", f"--method={method}", "--quiet", "--json", out, "--plot", _os.path.join(tmp, "i.png")]
        names: Dict[str, str] = {}
        for i, m in enumerate(_mechanism_list(mechanisms)):
            if json is not None:
                mech = _mechanism_file(f"mechanisms[{i}]", m, _beside(out, i), {})
            else:
                mech = _mechanism_file(f"mechanisms[{i}]", m, _os.path.join(tmp, f"mechanism{i}.toml"), names)
            args += ["--mechanism", mech]
        args += _paths("runs", runs)
        _run(args, echo, names)
        return Identification(json=_read_json(out))


def _mechanism_list(value: Any) -> List[Any]:
    if isinstance(value, (str, _os.PathLike, Mechanism)):
        return [value]
    if value is None or isinstance(value, Mapping) or not isinstance(value, (list, tuple)):
        raise InputError(
            "mechanisms: expected a mechanism (a file name or a Mechanism) or a list of them, "
            f"got {type(value).__name__}"
        )
    if not value:
        raise InputError("mechanisms: expected at least one mechanism, got an empty list")
    return list(value)


def diagnose(
    runs: Union[PathLike, Sequence[PathLike]],
    mechanisms: Union[MechanismLike, Sequence[MechanismLike]],
    json: PathLike,
    max_effects: int = 3,
    max_seconds: Optional[float] = None,
    echo: bool = False,
) -> Diagnosis:
    """``deploywatch diagnose``: the named causes of what the model gets
    wrong in the measured runs; the findings JSON written to ``json``, the
    report (``.md``) and plots beside it, and a mechanism given in memory
    (not as its unchanged file) as ``<stem>.mechanism<i>.toml``, so that
    the commands the report shows run as written. ``max_seconds`` stops
    the search and writes the best model found so far, marked as such; so
    does Ctrl-C (as the CLI's), in the first ``diagnose`` of the process
    (the signal handler of the Rust crate it uses can be set once; in
    later calls Ctrl-C is seen when the call returns: use
    ``max_seconds``)."""
    out = _path("json", json)
    args = ["diagnose", "--json", out, "--quiet", f"--max-effects={_whole('max_effects', max_effects)}"]
    if max_seconds is not None:
        args += ["--max-seconds", repr(_real("max_seconds", max_seconds))]
    run_files = _paths("runs", runs)
    for i, m in enumerate(_mechanism_list(mechanisms)):
        args += ["--mechanism", _mechanism_file(f"mechanisms[{i}]", m, _beside(out, i), {})]
    args += run_files
    # The command takes Ctrl-C (its handler replaces Python's for the
    # call: the search stops and the best model so far is written,
    # marked, as the CLI does); Python's handler is put back after.
    main = _threading.current_thread() is _threading.main_thread()
    python_handler = _signal.getsignal(_signal.SIGINT) if main else None
    try:
        _run(args, echo)
    finally:
        if python_handler is not None:
            _signal.signal(_signal.SIGINT, python_handler)
    return Diagnosis(json=_read_json(out), report=_os.path.splitext(out)[0] + ".md")


def replay(run: PathLike, mechanism: MechanismLike, out: Optional[PathLike] = None, echo: bool = False) -> Replay:
    """``deploywatch replay --target host``: the run through the on-board
    monitor (the core's ``f32`` code on the host); its status stream as
    numpy columns (``out`` keeps the CSV)."""
    with _tempfile.TemporaryDirectory() as tmp:
        path = _path("out", out) if out is not None else _os.path.join(tmp, "status.csv")
        names: Dict[str, str] = {}
        mech = _mechanism_file("mechanism", mechanism, _os.path.join(tmp, "mechanism0.toml"), names)
        args = ["replay", _existing("run", run), "--mechanism", mech]
        args += ["--target", "host", "--quiet", "--out", path]
        _run(args, echo, names)
        return _read_columns(path)


#: The status CSV's text columns (docs/monitor.md, the columns without a
#: unit; `host-sim/src/onboard/replay/status_csv.rs` writes them): always
#: in ``states``, whatever a run holds, so that ``faults1`` of a run
#: without a fault (every value empty) is text as it is in a run with one.
_TEXT_COLUMN = _re.compile(r"(viscous\d+_obs|latch\d+|prediction\d+|faults\d+|resolution\d+)")


def _read_columns(path: str) -> Replay:
    """A CSV the CLI wrote (comment lines skipped): the status CSV's text
    columns (``_TEXT_COLUMN``) as tuples; every other column as numpy (NaN
    where empty) when its values are numbers, else as tuples."""
    with open(path, encoding="utf-8") as f:
        rows = [r for r in _csv.reader(line for line in f if not line.startswith("#"))]
    head, body = rows[0], rows[1:]
    cols: Dict[str, FloatArray] = {}
    states: Dict[str, Tuple[str, ...]] = {}
    for k, name in enumerate(head):
        texts = [r[k] for r in body]
        if _TEXT_COLUMN.fullmatch(name):
            states[name] = tuple(texts)
            continue
        try:
            cols[name] = _np.array([_np.nan if x == "" else float(x) for x in texts], dtype=_np.float64)
        except ValueError:
            states[name] = tuple(texts)
    return Replay(columns=cols, states=states)


@dataclass(frozen=True)
class Hil:
    """``deploywatch hil``: ``statuses`` the statuses the firmware sent
    back (the columns of ``replay``), ``latency`` each sample's fate, send
    time and latency (the columns of ``--latency``)."""

    statuses: Replay
    latency: Replay


def hil(
    run: PathLike,
    mechanism: MechanismLike,
    elf: Optional[PathLike] = None,
    port: Optional[str] = None,
    baud: int = 921_600,
    duration: Optional[float] = None,
    every: int = 1,
    drop: float = 0.0,
    corrupt: float = 0.0,
    delay: Optional[str] = None,
    seed: int = 1,
    icount: Optional[int] = None,
    require_deadlines: bool = False,
    out: Optional[PathLike] = None,
    latency: Optional[PathLike] = None,
    echo: bool = False,
) -> Hil:
    """``deploywatch hil``: the run sent sample by sample, in real time, to
    the serial-link firmware — under QEMU (``elf``, by default the one
    ``scripts/firmware.sh build`` makes) or on a board on ``port`` — and
    its statuses checked against the core's on the host, as the CLI does
    (a mismatch raises ``DeploywatchError``; ``require_deadlines``: a late
    status too). ``drop``, ``corrupt``, ``delay`` inject link faults."""
    with _tempfile.TemporaryDirectory() as tmp:
        status = _path("out", out) if out is not None else _os.path.join(tmp, "status.csv")
        lat = _path("latency", latency) if latency is not None else _os.path.join(tmp, "latency.csv")
        names: Dict[str, str] = {}
        mech = _mechanism_file("mechanism", mechanism, _os.path.join(tmp, "mechanism0.toml"), names)
        args = ["hil", _existing("run", run), "--mechanism", mech]
        args += ["--quiet", "--out", status, "--latency", lat, "--baud", str(_whole("baud", baud))]
        args += ["--every", str(_whole("every", every)), "--drop", repr(_real("drop", drop)), "--corrupt", repr(_real("corrupt", corrupt))]
        args += ["--seed", str(_whole("seed", seed))]
        if port is not None:
            args += ["--target", "serial", f"--port={port}"]
        else:
            args += ["--target", "qemu"]
        if elf is not None:
            args += ["--elf", _existing("elf", elf)]
        if duration is not None:
            args += ["--duration", repr(_real("duration", duration))]
        if delay is not None:
            args.append(f"--delay={delay}")
        if icount is not None:
            args += ["--icount", str(_whole("icount", icount))]
        if _bool("require_deadlines", require_deadlines):
            args.append("--require-deadlines")
        _run(args, echo, names)
        return Hil(statuses=_read_columns(status), latency=_read_columns(lat))
