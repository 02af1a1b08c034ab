"""The type checks of the arguments Python users give: a number where a
number is meant, a whole number where a count or a joint is, each refused
with an ``InputError`` that names the argument (never ``float()``'s
``ValueError`` or a ``TypeError`` from deep inside)."""

from __future__ import annotations

from typing import Any, Callable, Type, TypeVar

import numpy as _np

from ._errors import InputError

_T = TypeVar("_T")


def _real(name: str, value: Any) -> float:
    """A real number (not a bool, not text), as the CLI reads it."""
    if isinstance(value, bool) or not isinstance(value, (int, float, _np.integer, _np.floating)):
        raise InputError(f"{name}: expected a number, got {type(value).__name__} {value!r}")
    return float(value)


def _whole(name: str, value: Any) -> int:
    """A whole number (not a bool, not text, not a float)."""
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise InputError(f"{name}: expected an integer, got {type(value).__name__} {value!r}")
    return int(value)


#: The check of each annotation a typed argument's field may carry.
_FIELD_CHECKS: dict[str, Callable[[str, Any], Any]] = {
    "int": _whole,
    "float": _real,
    "Optional[int]": lambda name, v: v if v is None else _whole(name, v),
    "Optional[float]": lambda name, v: v if v is None else _real(name, v),
}


def checked(cls: Type[_T]) -> Type[_T]:
    """Gives a dataclass (decorated under ``@dataclass``) a
    ``__post_init__`` checking each field annotated ``int``, ``float`` or
    their ``Optional``: ``Coulomb(joint="1", torque_nm=0.5)`` raises
    ``InputError: Coulomb.joint: expected an integer, got str '1'`` where
    it is written, not when a command first reads it."""
    fields = [(n, _FIELD_CHECKS[t]) for n, t in cls.__annotations__.items() if t in _FIELD_CHECKS]

    def __post_init__(self: Any) -> None:
        for name, check in fields:
            check(f"{cls.__name__}.{name}", getattr(self, name))

    setattr(cls, "__post_init__", __post_init__)
    return cls
