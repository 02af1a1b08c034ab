"""The type checks of the arguments Python users give: a number where a
number is meant, a whole number where a count or a joint is, a file's name
(of a file that exists, not a folder) where a file is, each refused with
an ``InputError`` that names the argument (never ``float()``'s
``ValueError``, ``open``'s ``IsADirectoryError`` or a ``TypeError`` from
deep inside)."""

from __future__ import annotations

import math as _math
import os as _os
import re as _re
from typing import Any, Callable, Type, TypeVar

import numpy as _np

from ._errors import InputError, MissingFileError

_T = TypeVar("_T")


def _real(name: str, value: Any) -> float:
    """A real number (not a bool, not text), as the CLI reads it."""
    if isinstance(value, bool) or not isinstance(value, (int, float, _np.integer, _np.floating)):
        raise InputError(f"{name}: expected a number, got {type(value).__name__} {value!r}")
    return float(value)


def _finite(name: str, value: Any, what: str = "a finite number") -> float:
    """A real number that is finite (``what`` says what it stands for)."""
    v = _real(name, value)
    if not _math.isfinite(v):
        raise InputError(f"{name}: expected {what}, got {v}")
    return v


def _positive(name: str, value: Any, what: str = "a positive finite number") -> float:
    """A real number that is finite and above 0."""
    v = _real(name, value)
    if not (_math.isfinite(v) and v > 0.0):
        raise InputError(f"{name}: expected {what}, got {v}")
    return v


def _string(name: str, value: Any) -> str:
    """A string (not bytes, not a number)."""
    if not isinstance(value, str):
        raise InputError(f"{name}: expected a string, got {type(value).__name__} {value!r}")
    return value


def _bool(name: str, value: Any) -> bool:
    """``True`` or ``False`` (numpy's too), never a number or text read as one."""
    if not isinstance(value, (bool, _np.bool_)):
        raise InputError(f"{name}: expected True or False, got {type(value).__name__} {value!r}")
    return bool(value)


def _whole(name: str, value: Any) -> int:
    """A whole number (not a bool, not text, not a float)."""
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise InputError(f"{name}: expected an integer, got {type(value).__name__} {value!r}")
    return int(value)


#: A TOML key line's start (``name = ...``): a "file name" that reads so is
#: a file's text given in its place.
_TOML_KEY = _re.compile(r"\s*[A-Za-z0-9_.\"-]+\s*=")


def _file_name(name: str, value: Any) -> str:
    """A file name (``str`` or ``os.PathLike``) of a file that exists:
    ``MissingFileError`` (an ``InputError`` and a ``FileNotFoundError``)
    naming the argument when it does not or names a folder, and an
    ``InputError`` that says so when what was given is a file's text
    (several lines, or a TOML key line) rather than its name."""
    if not isinstance(value, (str, _os.PathLike)):
        raise InputError(f"{name}: expected a file name (str or pathlib.Path), got {type(value).__name__}")
    p = _os.fspath(value)
    if not isinstance(p, str):
        raise InputError(f"{name}: expected a file name as text, got {type(p).__name__}")
    if _os.path.isdir(p):
        raise MissingFileError(f"{name}: {p}: is a folder, not a file", filename=p, folder=True)
    if _os.path.exists(p):
        return p
    if "\n" in p or (_TOML_KEY.match(p) and not p.endswith(".toml")):
        first = next((line.strip() for line in p.splitlines() if line.strip()), "")
        raise InputError(
            f"{name}: expected a file name, got a file's text ({first!r} ...): "
            "give its name, or parse a mechanism's text with Mechanism.from_str(text)"
        )
    raise MissingFileError(f"{name}: {p}: no such file", filename=p)


def _read_text(name: str, value: Any) -> "tuple[str, str]":
    """The text and the name of a file (``_file_name``), refused with an
    ``InputError`` naming the argument, the file and the first byte that is
    not UTF-8 when it is not text (a binary or a file saved in another
    encoding), as the CLI refuses it."""
    p = _file_name(name, value)
    try:
        with open(p, encoding="utf-8") as f:
            return f.read(), p
    except UnicodeDecodeError as e:
        raise InputError(
            f"{name}: {p}: byte {e.start} (0x{e.object[e.start]:02x}) is not UTF-8: "
            "expected a text file saved as UTF-8"
        ) from None
    except OSError as e:
        raise InputError(f"{name}: {p}: cannot be read: {e.strerror}") from None


def _argument_path(p: str) -> str:
    """A relative file name that starts with ``-`` as ``./-name``: the
    command line would take it for a flag."""
    return _os.path.join(".", p) if p.startswith("-") else p


#: The check of each annotation a typed argument's field may carry.
_FIELD_CHECKS: dict[str, Callable[[str, Any], Any]] = {
    "str": _string,
    "int": _whole,
    "float": _real,
    "Optional[int]": lambda name, v: v if v is None else _whole(name, v),
    "Optional[float]": lambda name, v: v if v is None else _real(name, v),
}


def checked(cls: Type[_T]) -> Type[_T]:
    """Gives a dataclass (decorated under ``@dataclass``) a
    ``__post_init__`` checking each field annotated ``str``, ``int``,
    ``float`` or their ``Optional``: ``Coulomb(joint="1", torque_nm=0.5)``
    raises ``InputError: Coulomb.joint: expected an integer, got str '1'``
    where it is written, not when a command first reads it. The class's own
    ``_check_values(self)``, if it has one, runs after those: the checks of
    values that need no mechanism (a law's standard deviation above 0, a
    criterion's threshold), each naming ``Class.field``."""
    fields = [(n, _FIELD_CHECKS[t]) for n, t in cls.__annotations__.items() if t in _FIELD_CHECKS]
    values = cls.__dict__.get("_check_values")

    def __post_init__(self: Any) -> None:
        for name, check in fields:
            check(f"{cls.__name__}.{name}", getattr(self, name))
        if values is not None:
            values(self)

    setattr(cls, "__post_init__", __post_init__)
    return cls
