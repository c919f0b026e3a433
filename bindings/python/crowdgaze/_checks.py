"""Checked conversions of scalar arguments at the edge of the binding.

Every integer, real number and flag a wrapper passes to C goes through here first, so
that a wrong value raises an exception naming the caller's argument before any handle is
taken, instead of being masked to the C type (``2**32 + 5`` becoming 5) or rejected by
ctypes with a nameless ``ArgumentError``.

Conventions (the same for every function and struct field of the package):

- An integer argument takes an ``int``, a numpy integer or any object with ``__index__``;
  ``bool`` (and ``numpy.bool_``) is refused (``TypeError``), as are floats, even integral
  ones. A value outside the C type's range (``uint32``: 0 to 2**32 - 1; ``size_t`` and
  ``uint64``: 0 to 2**64 - 1) raises ``OverflowError``.
- A real argument takes an ``int``, a ``float``, a numpy number (or 0-d array of one) or
  any object with ``__float__`` (or ``__index__``); ``bool``, strings, bytes, arrays and
  complex numbers are refused (``TypeError``). A finite value too large for a C ``float``
  raises ``OverflowError``; NaN and infinities are passed on, for the C library to refuse
  where its contract does.
- A flag (C ``bool``) takes ``True``/``False`` (or ``numpy.bool_``) only.
- A string (C ``const char *``, NUL-terminated UTF-8) takes a ``str`` that encodes to UTF-8
  (no lone surrogates) and holds no NUL character; anything else raises ``TypeError``, a
  string C could not read whole ``ValueError``.

Messages start with the Python function (``Crowd.step``) and name the argument or field.
"""

from __future__ import annotations

import ctypes
import math
import operator

import numpy as np

from . import _exceptions as e

#: Largest finite C float.
FLOAT32_MAX = float(np.finfo(np.float32).max)
#: Doubles at least this large in magnitude round to an infinite C float (half-way between
#: FLOAT32_MAX and 2**128, which rounds to even: up).
FLOAT32_OVERFLOW = 2.0**128 - 2.0**103

#: The unsigned C types integer arguments and fields have: name -> largest value.
UNSIGNED = {
    "uint32": 2**32 - 1,
    "uint64": 2**64 - 1,
    "size_t": 2 ** (8 * ctypes.sizeof(ctypes.c_size_t)) - 1,
}


def describe(value) -> str:
    """A short, safe description of ``value`` for an error message (never raises)."""
    try:
        text = repr(value)
    except Exception:  # a hostile __repr__: fall back on the type
        return f"a {type(value).__name__}"
    if len(text) > 60:
        text = text[:57] + "..."
    return text


def _refused_number(value) -> bool:
    if isinstance(value, np.ndarray):  # a 0-d array of a number is one; others are not
        return value.ndim != 0 or value.dtype.kind not in "fiu"
    return value is None or isinstance(
        value, (bool, np.bool_, str, bytes, bytearray, memoryview, complex)
    )


def integer(value, where: str, name: str, ctype: str = "uint32") -> int:
    """``value`` as a Python ``int`` in the range of the unsigned C type ``ctype``."""
    largest = UNSIGNED[ctype]
    if isinstance(value, (bool, np.bool_)):
        raise e.type_error(f"{where}: {name} must be an integer, got a bool ({value!r})")
    try:
        result = operator.index(value)
    except TypeError:
        raise e.type_error(
            f"{where}: {name} must be an integer, got {describe(value)} "
            f"({type(value).__name__})"
        ) from None
    if not 0 <= result <= largest:
        raise e.range_error(
            f"{where}: {name} must be an integer in 0..{largest} ({ctype}), got {result}"
        )
    return result


def real(value, where: str, name: str, single: bool = True) -> float:
    """``value`` as a Python ``float``; with ``single``, one a C ``float`` can hold (a finite
    value beyond its range raises ``OverflowError``; NaN and infinities pass)."""
    if _refused_number(value) or not (
        hasattr(type(value), "__float__") or hasattr(type(value), "__index__")
    ):
        raise e.type_error(
            f"{where}: {name} must be a real number, got {describe(value)} "
            f"({type(value).__name__})"
        )
    try:
        result = float(value)
    except OverflowError:
        raise e.range_error(
            f"{where}: {name} is too large for a float: {describe(value)}"
        ) from None
    except Exception as error:
        raise e.type_error(
            f"{where}: {name} must be a real number, converting {describe(value)} failed: "
            f"{error}"
        ) from error
    if single and math.isfinite(result) and abs(result) >= FLOAT32_OVERFLOW:
        raise e.range_error(
            f"{where}: {name} is out of the range of a C float (at most {FLOAT32_MAX:g} "
            f"in magnitude), got {result!r}"
        )
    return result


def flag(value, where: str, name: str) -> bool:
    """``value`` as a ``bool``: only ``True``/``False`` (or ``numpy.bool_``)."""
    if not isinstance(value, (bool, np.bool_)):
        raise e.type_error(
            f"{where}: {name} must be True or False, got {describe(value)} "
            f"({type(value).__name__})"
        )
    return bool(value)


def instance(value, ctype, where: str, name: str):
    """``value`` itself if it is a ``ctype`` (a ctypes struct), else ``TypeError``."""
    if not isinstance(value, ctype):
        raise e.type_error(
            f"{where}: {name} must be a crowdgaze.{ctype.__name__}, got {describe(value)} "
            f"({type(value).__name__})"
        )
    return value


def text(value, where: str, name: str) -> bytes:
    """``value`` (a ``str``) as the NUL-terminated UTF-8 a C string holds, without the NUL:
    ``TypeError`` for anything but a ``str``, ``ValueError`` for a string that does not
    encode to UTF-8 (a lone surrogate) or holds a NUL character (C would read it cut)."""
    if not isinstance(value, str):
        raise e.type_error(
            f"{where}: {name} must be a str, got {describe(value)} ({type(value).__name__})"
        )
    try:
        encoded = value.encode("utf-8")
    except UnicodeEncodeError as error:
        raise e.value_error(
            f"{where}: {name} is not valid UTF-8 text ({error.reason} at index "
            f"{error.start}): {describe(value)}"
        ) from None
    if b"\0" in encoded:
        raise e.value_error(
            f"{where}: {name} holds a NUL character at index {value.index(chr(0))}; C strings "
            f"end at the first NUL: {describe(value)}"
        )
    return encoded
