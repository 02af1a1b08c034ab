"""The functions of deploywatch: arguments checked here (each error names
the argument and what was expected), the work done by the extension
(``deploywatch._native``), the results typed (``_results``)."""

from __future__ import annotations

import math as _math
import os as _os
import sys as _sys
from typing import Any, Callable, List, Optional, Protocol, Sequence, Union

import numpy as _np
import numpy.typing as _npt

from . import _native
from ._checks import _bool, _read_text
from ._errors import InputError
from ._model import CriterionLike, EffectLike, Mechanism, PathLike, VaryLike, strings
from ._results import Batch, FloatArray, Reliability, Trajectory

MechanismLike = Union[PathLike, Mechanism]
"""A mechanism: a file name (``str`` or ``pathlib.Path``) or a parsed
:class:`Mechanism`."""


class Future(Protocol):
    """What ``executor.submit`` returns: a future with ``result()``."""

    def result(self) -> Any: ...

    def cancel(self) -> Any: ...


class Executor(Protocol):
    """An executor of tasks: ``concurrent.futures.Executor``,
    ``dask.distributed.Client`` or anything with ``submit(fn, *args)``."""

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Any: ...


def _text(name: str, path: Any) -> "tuple[str, str]":
    """The text and the name of a file given by path (or of a parsed
    :class:`Mechanism`)."""
    if isinstance(path, Mechanism):
        return path.toml, path.source
    return _read_text(name, path)


def _from_text(from_: Optional[PathLike]) -> Optional[str]:
    return None if from_ is None else _text("from_", from_)[0]


def _strings(name: str, value: Any) -> List[str]:
    """A list of strings, refusing the classic slip of a single string
    (which Python would iterate character by character)."""
    if isinstance(value, (str, bytes)):
        raise InputError(f"{name}: expected a list of strings, e.g. [{value!r}], got a single string")
    try:
        items = list(value)
    except TypeError:
        raise InputError(f"{name}: expected a list of strings, got {type(value).__name__}") from None
    for i, v in enumerate(items):
        if not isinstance(v, str):
            raise InputError(f"{name}[{i}]: expected a string, got {type(v).__name__} {v!r}")
    return items


def _int(name: str, value: Any, low: int, high: Optional[int] = None) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise InputError(f"{name}: expected an integer, got {type(value).__name__} {value!r}")
    v = int(value)
    if v < low or (high is not None and v > high):
        top = "" if high is None else f" and at most {high}"
        raise InputError(f"{name}: expected an integer of at least {low}{top}, got {v}")
    return v


def _positive(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, _np.integer, _np.floating)):
        raise InputError(f"{name}: expected a positive number, got {type(value).__name__} {value!r}")
    v = float(value)
    if not (_math.isfinite(v) and v > 0.0):
        raise InputError(f"{name}: expected a positive finite number, got {v}")
    return v


def _matrix(name: str, value: Any, labels: Sequence[str]) -> FloatArray:
    """``value`` as a C-contiguous float64 matrix of one column per
    parameter, or an InputError that says which shape and dtype it wanted."""
    d = len(labels)
    want = f"a 2-D array of real numbers of shape (n, {d}), one column per parameter ({', '.join(labels)})"
    value = _by_label(name, value, labels)
    if isinstance(value, _np.ma.MaskedArray) and _np.ma.is_masked(value):
        at = [int(k) for k in _np.argwhere(_np.ma.getmaskarray(value))[0]]
        raise InputError(f"{name}{at}: masked; expected every entry given (a masked array's mask would be dropped)")
    try:
        a = _np.asarray(value)
    except (ValueError, TypeError) as e:
        raise InputError(f"{name}: expected {want}; got rows of unequal length or non-numbers ({e})") from None
    if a.dtype.kind not in "iuf":
        raise InputError(f"{name}: expected {want}; got an array of dtype {a.dtype}")
    if a.ndim == 1 and d == 1:
        a = a.reshape(-1, 1)
    if a.ndim != 2 or a.shape[1] != d:
        hint = f" (one point is [[{', '.join(['...'] * d)}]])" if a.ndim == 1 else ""
        raise InputError(f"{name}: expected {want}; got shape {a.shape}{hint}")
    out = _np.ascontiguousarray(a, dtype=_np.float64)
    bad = _np.argwhere(~_np.isfinite(out))
    if bad.size:
        i, j = (int(k) for k in bad[0])
        raise InputError(f"{name}[{i}, {j}] ({labels[j]}): expected a finite number, got {out[i, j]}")
    return out


def _by_label(name: str, value: Any, labels: Sequence[str]) -> Any:
    """A table with named columns (a ``pandas.DataFrame``) in the order of
    ``labels``, taken by name: columns named otherwise are refused, naming
    them, rather than read in the order they stand. Columns numbered 0, 1,
    ... (a frame made from an array) and anything else are taken as given,
    by position."""
    columns = getattr(value, "columns", None)
    if columns is None or not hasattr(value, "loc"):
        return value
    names = list(columns)
    if all(isinstance(c, (int, _np.integer)) and not isinstance(c, bool) for c in names):
        return value
    unknown = [c for c in names if c not in labels]
    missing = [c for c in labels if c not in names]
    if unknown or missing or len(set(names)) != len(names):
        raise InputError(
            f"{name}: a table's columns are taken by name, expected the parameters "
            f"({', '.join(labels)}); unknown: {', '.join(map(str, unknown)) or 'none'}, "
            f"missing: {', '.join(missing) or 'none'}"
            + ("; a column given twice" if len(set(names)) != len(names) else "")
        )
    return value[list(labels)]


def simulate(
    mechanism: MechanismLike,
    effects: Sequence[EffectLike] = (),
    sample_hz: Optional[float] = None,
) -> Trajectory:
    """One deployment of the mechanism (``deploywatch simulate``), with
    extra effects, typed (``Coulomb(joint=1, torque_nm=1.2)``) or in the
    ``--effect`` syntax (``"coulomb_friction:joint=1:value=1.2"``), checked
    as the CLI checks ``--effect`` (a sensor effect, ``EncoderOffset``, is
    refused: it moves no joint, and this is the motion), sampled at
    ``sample_hz`` [Hz] (default: the file's rate).

    Returns a :class:`Trajectory`: ``t_s`` (n,), ``phi_deg`` and
    ``rate_deg_s`` (n, joints), ``latch_s`` (joints,), NaN where not
    latched, ``end_s`` the time of the last sample (``t_s[-1]``),
    ``last_latch_s`` when the last joint latched.

    Raises ``MechanismError`` for a bad file, ``InputError`` for a bad
    effect or rate, ``SimulationError`` if the equations cannot be
    integrated.
    """
    if not isinstance(mechanism, Mechanism):
        text, source = _text("mechanism", mechanism)
        mechanism = Mechanism.from_str(text, source)
    return mechanism.simulate(effects, sample_hz)


def parameters(
    mechanism: MechanismLike,
    vary: Sequence[VaryLike] = (),
    fail: Sequence[CriterionLike] = ("not_latched",),
    from_: Optional[PathLike] = None,
    flight: bool = False,
) -> List[str]:
    """The parameters of the problem (``vary``, then those of ``from_``,
    an ``identify --json`` file), in the column order of ``params`` of
    :func:`simulate_batch`; ``flight`` as :func:`reliability`'s."""
    text, source = _text("mechanism", mechanism)
    return _native.parameters(
        text,
        source,
        strings("vary", vary),
        strings("fail", fail),
        _from_text(from_),
        _bool("flight", flight),
    )


def simulate_batch(
    mechanism: MechanismLike,
    vary: Sequence[VaryLike],
    params: _npt.ArrayLike,
    fail: Sequence[CriterionLike] = ("not_latched",),
    from_: Optional[PathLike] = None,
    flight: bool = False,
) -> Batch:
    """One deployment per row of ``params`` (numbers, shape (n, parameters):
    one column per ``vary`` parameter, then those of ``from_``, in the order
    of :func:`parameters`; a 1-D array when there is one parameter; a
    ``pandas.DataFrame`` whose columns are named by :func:`parameters`'s
    labels is taken by name, in any order). The
    loop runs in Rust on every core with the GIL released; Ctrl-C stops it.

    Returns a :class:`Batch`: ``g`` (n,) (failure iff ``g <= 0``),
    ``margins`` (n, modes: one per ``fail`` criterion and joint, failed iff
    ``<= 0``), ``latch_s``, ``latch_rate_deg_s`` (n, joints; NaN where not
    latched; the rate only with a ``latch_rate>X`` criterion in ``fail``),
    ``end_deg`` (n, joints). ``flight``: the flight unit, as
    :func:`reliability`'s.

    Raises ``InputError`` naming the argument (a ``vary``/``fail`` string,
    the shape, dtype or a non-finite entry of ``params``),
    ``MechanismError``, ``SimulationError`` for a deployment that cannot be
    simulated (with its parameters).
    """
    text, source = _text("mechanism", mechanism)
    vs, fs, fj = strings("vary", vary), strings("fail", fail), _from_text(from_)
    fl = _bool("flight", flight)
    labels = _native.parameters(text, source, vs, fs, fj, fl)
    rows = _matrix("params", params, labels)
    return Batch(*_native.simulate_batch(text, source, vs, fs, rows, fj, fl))


def _g_chunk(
    text: str,
    source: str,
    vary: List[str],
    fail: List[str],
    from_json: Optional[str],
    flight: bool,
    rows: FloatArray,
) -> FloatArray:
    """The margins of every failure mode (n, modes) of a chunk of rows: the
    task an executor runs."""
    return _native.simulate_batch(text, source, vary, fail, rows, from_json, flight)[1]


def _check_open(executor: Executor) -> None:
    """A ``dask.distributed.Client`` that is closed (or closing) cannot take
    a task: an ``InputError`` naming ``executor``, before a task is sent,
    not the ``ClosedClientError`` Dask raises from inside the analysis.
    Other executors are left to their own ``submit``."""
    distributed = _sys.modules.get("distributed")
    client = getattr(distributed, "Client", None)
    if not (isinstance(client, type) and isinstance(executor, client)):
        return
    status = str(getattr(executor, "status", "running"))
    # "running"; "connecting" while it reconnects to its scheduler (its
    # tasks wait for it); "newly-created" for an asynchronous client not
    # yet awaited, which this synchronous call cannot use either.
    if status not in ("running", "connecting"):
        state = status if status in ("closed", "closing") else "not running"
        raise InputError(
            f"executor: the dask.distributed.Client is {state} (status {status!r}) and cannot take "
            "tasks: pass an open one (a Client used inside its `with` block, or before "
            "client.close()), or executor=None to run on this machine's cores"
        )


def _workers(executor: Executor, workers: Optional[int]) -> int:
    """How many tasks the executor runs at once (for the chunk size only):
    ``workers`` if given, else a Dask client's worker count
    (``Client.scheduler_info()``), else this machine's cores."""
    if workers is not None:
        return workers
    info = getattr(executor, "scheduler_info", None)
    if callable(info):
        return max(1, len(info().get("workers", {})))
    return _os.cpu_count() or 1


def _evaluator(
    executor: Executor, chunk: Optional[int], workers: int, task: "tuple[Any, ...]"
) -> Callable[[FloatArray], List[List[float]]]:
    def evaluate(xs: FloatArray) -> List[List[float]]:
        # A client closed during the analysis (another thread, a timeout):
        # said as before the first batch.
        _check_open(executor)
        n = xs.shape[0]
        size = chunk or max(1, -(-n // workers // 4))
        futures = [executor.submit(_g_chunk, *task, xs[i : i + size]) for i in range(0, n, size)]
        try:
            return _np.concatenate([f.result() for f in futures]).tolist()  # type: ignore[no-any-return]
        except BaseException:
            # A failed task or Ctrl-C: the other tasks are not wanted.
            for f in futures:
                cancel = getattr(f, "cancel", None)
                if callable(cancel):
                    cancel()
            raise

    return evaluate


def reliability(
    mechanism: MechanismLike,
    vary: Sequence[VaryLike] = (),
    fail: Sequence[CriterionLike] = ("not_latched",),
    method: str = "auto",
    samples: Optional[int] = None,
    target_cov: Optional[float] = None,
    seed: int = 0,
    from_: Optional[PathLike] = None,
    executor: Optional[Executor] = None,
    chunk: Optional[int] = None,
    corr: Sequence[str] = (),
    workers: Optional[int] = None,
    flight: bool = False,
) -> Reliability:
    """``deploywatch reliability`` as a function: the CLI's options as
    keyword arguments, its JSON as a :class:`Reliability` (``.to_dict()``
    is that JSON's dict, equal bit for bit).

    ``vary``: ``--vary`` strings (e.g.
    ``"coulomb_friction:joint=1:lognormal(2.63,0.05)"``); ``fail``:
    ``--fail`` criteria; ``method``: ``"auto"`` (importance sampling and
    subset simulation, checked against each other), ``"is"``, ``"subset"``
    or ``"mc"``; ``samples``, ``target_cov``, ``seed`` as the CLI's; ``from_``: an ``identify --json``
    file; ``corr``: ``"I,J,RHO"`` strings, as ``--corr``; ``flight``: the
    flight unit, as ``--flight`` (the mechanism's ``[rig]`` taken out, the
    rig-only effects of ``from_`` drawn in no deployment and the wing's
    losses the runs could not tell from them drawn in their place, each
    said in a ``UserWarning``).

    ``executor``: ``None`` for every local core (rayon, the GIL released),
    or any object with ``submit(fn, *args)`` returning futures with
    ``result()``: a ``concurrent.futures.Executor`` or a
    ``dask.distributed.Client``. Each batch of deployments is cut into
    chunks of ``chunk`` rows (default: about four per worker; ``workers``
    tells how many tasks run at once, default the Dask client's workers or
    this machine's cores) and submitted there. The result equals the local
    one bit for bit (each task returns the margins of every failure mode
    of its rows). An error raised by a task (e.g. a ``SimulationError``
    on a Dask worker) is raised here as it is. A Dask client that is
    closed (before the call or during it) is an ``InputError`` naming
    ``executor``.

    Ctrl-C stops the analysis between batches (``KeyboardInterrupt``).
    Raises ``InputError`` (``MechanismError``) for bad arguments,
    ``SimulationError`` for a deployment that cannot be simulated,
    ``EvaluatorError`` for an executor's unusable answer. Warns
    (``UserWarning``, what the CLI says on stderr) when the most likely
    failure seen fails ``not_latched`` at a joint its physical latch holds
    with its switch open at the end: ``NotHeld`` counts what the latch does.
    """
    text, source = _text("mechanism", mechanism)
    from_json = _from_text(from_)
    vs, fs, cs = strings("vary", vary), strings("fail", fail), _strings("corr", corr)
    fl = _bool("flight", flight)
    if not isinstance(method, str):
        raise InputError(f"method: expected \"auto\", \"is\", \"subset\" or \"mc\", got {type(method).__name__}")
    n = None if samples is None else _int("samples", samples, 1)
    cov = None if target_cov is None else _positive("target_cov", target_cov)
    sd = _int("seed", seed, 0, 2**64 - 1)
    evaluate = None
    if executor is not None:
        if not callable(getattr(executor, "submit", None)):
            raise InputError(
                f"executor: expected a concurrent.futures.Executor or a dask.distributed.Client "
                f"(an object with submit(fn, *args)), got {type(executor).__name__}"
            )
        _check_open(executor)
        size = None if chunk is None else _int("chunk", chunk, 1)
        w = _workers(executor, None if workers is None else _int("workers", workers, 1))
        evaluate = _evaluator(executor, size, w, (text, source, vs, fs, from_json, fl))
    out = _native.reliability(text, source, vs, fs, method, n, cov, sd, from_json, evaluate, cs, fl)
    return Reliability.from_dict(out)
