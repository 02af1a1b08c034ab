"""The exceptions of deploywatch: one base class, one class per kind of
failure, each also a subclass of the built-in exception a Python user would
catch (``InputError`` is a ``ValueError``, ``SimulationError`` a
``RuntimeError``).

An error from the Rust core keeps its message (the CLI's words) and its
cause: ``__cause__`` is a ``DeploywatchError`` holding the Rust error's
source, and ``causes`` lists the whole chain as text. Both survive pickling,
so an error raised on a Dask worker (or in any process) arrives in the
caller as the same class, message and causes.
"""

from __future__ import annotations

import errno as _errno
from typing import Any, Optional, Sequence, Tuple, Type


class DeploywatchError(Exception):
    """Base class of every error deploywatch raises on purpose.

    ``message``: what went wrong (as the CLI says it); ``causes``: the
    underlying errors' messages, outermost first (empty if none).
    """

    def __init__(self, message: str, causes: Sequence[str] = ()) -> None:
        super().__init__(message)
        self.message = message
        self.causes: Tuple[str, ...] = tuple(causes)

    def __str__(self) -> str:
        return self.message

    def __reduce__(self) -> Tuple[Any, ...]:
        # BaseException pickles only `args` and `__dict__`: carry the cause
        # too, so that it crosses a process boundary (Dask, multiprocessing).
        return (_rebuild, (type(self), self.message, self.causes, self.__cause__))


class InputError(DeploywatchError, ValueError):
    """An argument is not usable: a ``vary``/``fail``/``corr``/effect string,
    the shape or dtype of an array, a setting out of range. The message names
    the argument and what was expected."""


class MissingFileError(InputError, FileNotFoundError):
    """A file given to read does not exist, or its name is a folder's: an
    ``InputError`` naming the argument, and a ``FileNotFoundError``
    (``filename``; ``errno.ENOENT``, or ``errno.EISDIR`` for a folder, as
    ``open`` gives), whichever function was given it."""

    def __init__(
        self,
        message: str,
        causes: Sequence[str] = (),
        filename: Optional[str] = None,
        folder: bool = False,
    ) -> None:
        super().__init__(message, causes)
        self.folder = folder
        self.errno = _errno.EISDIR if folder else _errno.ENOENT
        self.strerror = "Is a directory" if folder else "No such file or directory"
        self.filename = filename

    def __reduce__(self) -> Tuple[Any, ...]:
        return (_rebuild_missing, (self.message, self.causes, self.filename, self.folder))


class MechanismError(InputError):
    """The mechanism file is not valid TOML or not a valid mechanism (the
    message gives the file, the line and what was expected)."""


class SimulationError(DeploywatchError, RuntimeError):
    """A deployment could not be simulated (the message gives its parameters
    and the integrator's reason)."""


class EvaluatorError(DeploywatchError, RuntimeError):
    """The executor's answer to a batch of deployments is not usable (e.g.
    the wrong number of values)."""


def _rebuild(
    cls: Type[DeploywatchError],
    message: str,
    causes: Sequence[str],
    cause: Optional[BaseException],
) -> DeploywatchError:
    err = cls(message, causes)
    err.__cause__ = cause
    return err


def _rebuild_missing(
    message: str, causes: Sequence[str], filename: Optional[str], folder: bool = False
) -> "MissingFileError":
    return MissingFileError(message, causes, filename, folder)


_KINDS = {
    "error": DeploywatchError,
    "input": InputError,
    "mechanism": MechanismError,
    "simulation": SimulationError,
    "evaluator": EvaluatorError,
}


def _from_rust(kind: str, message: str, causes: Sequence[str]) -> DeploywatchError:
    """The exception for a Rust error (called by the extension): class by
    ``kind``, ``__cause__`` the chain of the Rust error's sources."""
    err = _KINDS[kind](message, causes)
    head: BaseException = err
    for i, text in enumerate(causes):
        link = DeploywatchError(text, causes[i + 1 :])
        head.__cause__ = link
        head = link
    return err
