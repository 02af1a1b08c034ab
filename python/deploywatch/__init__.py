"""deploywatch from Python.

- ``simulate(mechanism, effects=())``: one deployment (numpy arrays).
- ``simulate_batch(mechanism, vary, params, fail=("not_latched",))``: one
  deployment per row of ``params`` (the hot loop in Rust on every core, the
  GIL released): the limit state ``g`` and per joint latch instant, latch
  rate and end angle.
- ``reliability(mechanism, vary=..., fail=..., method="auto", ...)``: the
  options of ``deploywatch reliability`` as keyword arguments, the result as
  the CLI's JSON (a dict). ``executor=``: any ``concurrent.futures.Executor``
  or a ``dask.distributed.Client``; the batches of deployments are submitted
  there, the levels run here. The result equals the local one bit for bit
  (every deployment is deterministic, every draw comes from its own stream).

docs/reliability.md shows the same analysis on one machine, on a Dask
LocalCluster and on a cluster.
"""

import json
import os

import numpy as np

from . import _native

__all__ = ["simulate", "simulate_batch", "reliability", "parameters"]


def _text(mechanism):
    """The TOML text and the name of a mechanism file (a path)."""
    path = os.fspath(mechanism)
    with open(path, encoding="utf-8") as f:
        return f.read(), path


def _from_text(from_):
    if from_ is None:
        return None
    with open(os.fspath(from_), encoding="utf-8") as f:
        return f.read()


def simulate(mechanism, effects=(), sample_hz=None):
    """One deployment of the mechanism file with extra effects
    (``simulate --effect`` syntax). Returns a dict: ``t_s`` (n,),
    ``phi_deg`` and ``rate_deg_s`` (n, joints), ``latch_s`` (joints,), NaN
    where not latched, ``end_s``."""
    text, source = _text(mechanism)
    return _native.simulate(text, source, list(effects), sample_hz)


def parameters(mechanism, vary=(), fail=("not_latched",), from_=None):
    """The parameters of the problem, in the column order of ``params``."""
    text, source = _text(mechanism)
    return _native.parameters(text, source, list(vary), list(fail), _from_text(from_))


def simulate_batch(mechanism, vary, params, fail=("not_latched",), from_=None):
    """One deployment per row of ``params`` (float64, one column per
    ``vary`` parameter, then those of ``from_``). Returns a dict: ``g`` (n,)
    (failure iff g <= 0), ``latch_s``, ``latch_rate_deg_s`` (n, joints; NaN
    where not latched), ``end_deg`` (n, joints)."""
    text, source = _text(mechanism)
    params = np.ascontiguousarray(params, dtype=np.float64)
    if params.ndim == 1:
        params = params.reshape(-1, 1)
    return _native.simulate_batch(text, source, list(vary), list(fail), params, _from_text(from_))


def _g_chunk(text, source, vary, fail, from_json, rows):
    """The margins of every failure mode of a chunk of rows: the task an
    executor runs."""
    return _native.simulate_batch(text, source, vary, fail, rows, from_json)["margins"]


def _evaluator(executor, text, source, vary, fail, from_json, chunk):
    def evaluate(xs):
        n = xs.shape[0]
        size = chunk or max(1, -(-n // _workers(executor) // 4))
        futures = [
            executor.submit(_g_chunk, text, source, vary, fail, from_json, xs[i : i + size])
            for i in range(0, n, size)
        ]
        return np.concatenate([f.result() for f in futures]).tolist()

    return evaluate


def _workers(executor):
    """How many workers the executor has (for the chunk size only)."""
    info = getattr(executor, "scheduler_info", None)
    if callable(info):
        return max(1, len(info().get("workers", {})))
    return max(1, getattr(executor, "_max_workers", os.cpu_count() or 1))


def reliability(
    mechanism,
    vary=(),
    fail=("not_latched",),
    method="auto",
    samples=None,
    target_cov=None,
    seed=0,
    from_=None,
    executor=None,
    chunk=None,
    corr=(),
):
    """``deploywatch reliability`` as a function: returns its JSON as a dict.

    ``corr``: ``"I,J,RHO"`` strings, as ``--corr``.
    ``executor``: ``None`` for every local core (rayon), or any object with
    ``submit(fn, *args)`` returning futures with ``result()``: a
    ``concurrent.futures.Executor`` or a ``dask.distributed.Client``. Each
    batch of deployments is cut into chunks of ``chunk`` rows (default:
    about four per worker) submitted there.
    """
    text, source = _text(mechanism)
    from_json = _from_text(from_)
    vary, fail = list(vary), list(fail)
    evaluate = None
    if executor is not None:
        evaluate = _evaluator(executor, text, source, vary, fail, from_json, chunk)
    out = _native.reliability(
        text, source, vary, fail, method, samples, target_cov, seed, from_json, evaluate,
        list(corr),
    )
    return json.loads(out)
