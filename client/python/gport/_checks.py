"""Type checks of JSON values, both ways: what ``publish_vehicle`` sends
(checked before anything is sent) and the vehicle members of the daemon's
captures and status (checked as they are read). Each raises ValueError
naming the member (``where``) and what came instead; nothing checks a range:
gportd does, and names the field in its InvalidParams."""

from __future__ import annotations

import math
from typing import Any, Mapping

# How much of a wrong value an error quotes.
_SHOWN_CHARS = 60


def _wrong(where: str, what: str, value: Any) -> ValueError:
    shown = repr(value)
    if len(shown) > _SHOWN_CHARS:
        shown = shown[:_SHOWN_CHARS] + "..."
    kind = "null" if value is None else type(value).__name__
    return ValueError(f"{where} must be {what}, not {kind} {shown}")


def number(value: Any, where: str) -> float:
    """A finite int or float (not a bool), as a float."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _wrong(where, "a number", value)
    if isinstance(value, float) and not math.isfinite(value):
        raise _wrong(where, "a finite number", value)
    return float(value)


def optional_number(value: Any, where: str) -> float | None:
    return None if value is None else number(value, where)


def integer(value: Any, where: str) -> int:
    """An int, not a bool (nor a float, even a whole one)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise _wrong(where, "an integer", value)
    return value


def optional_integer(value: Any, where: str) -> int | None:
    return None if value is None else integer(value, where)


def flag(value: Any, where: str) -> bool:
    if not isinstance(value, bool):
        raise _wrong(where, "true or false", value)
    return value


def text(value: Any, where: str) -> str:
    if not isinstance(value, str):
        raise _wrong(where, "a string", value)
    return value


def triple(value: Any, where: str) -> tuple[float, float, float]:
    """Three numbers, in a list or a tuple (``velocity_ned``)."""
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise _wrong(where, "three numbers", value)
    first, second, third = (number(v, f"{where}[{i}]") for i, v in enumerate(value))
    return first, second, third


def mapping(value: Any, where: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise _wrong(where, "an object", value)
    return value
