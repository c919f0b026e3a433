"""numpy views of the C arrays: float rows (quaternions ``(n, 4)``, dual quaternions
``(n, 8)``, vectors ``(n, 3)``) and structured arrays laid out exactly as the C structs.

An input whose layout already fits (C-contiguous, the right dtype and last dimension) is
passed to C as it is, without a copy; anything else is converted (one copy). An output
array given by the caller is written in place when it fits; otherwise the result is
computed into a temporary and copied into it.
"""

from __future__ import annotations

import ctypes
from ctypes import POINTER

import numpy as np

from . import _native as n

#: ``cg_entity_state`` as a numpy record; ``position`` and ``velocity`` are ``float32[3]``.
ENTITY_STATE_DTYPE = np.dtype(
    [
        ("struct_size", "<u4"),
        ("id", "<u4"),
        ("flags", "<u4"),
        ("heading", "<f4"),
        ("position", "<f4", (3,)),
        ("velocity", "<f4", (3,)),
    ],
    align=True,
)

#: ``cg_gaze_info`` as a numpy record.
GAZE_INFO_DTYPE = np.dtype(
    [
        ("character", "<u4"),
        ("target", "<u4"),
        ("target_part", "<u4"),
        ("head_target", "<u4"),
        ("attending", "<u4"),
        ("interest_count", "<u4"),
        ("target_position", "<f4", (3,)),
        ("s_max", "<f4"),
        ("threshold", "<f4"),
        ("attentive_fraction", "<f4"),
    ],
    align=True,
)

#: ``cg_eye_info`` as a numpy record.
EYE_INFO_DTYPE = np.dtype(
    [
        ("character", "<u4"),
        ("left_origin", "<f4", (3,)),
        ("right_origin", "<f4", (3,)),
        ("left_direction", "<f4", (3,)),
        ("right_direction", "<f4", (3,)),
    ],
    align=True,
)

#: ``cg_constraint`` as a numpy record.
CONSTRAINT_DTYPE = np.dtype(
    [("entity", "<u4"), ("s_max", "<f4"), ("begin", "<f8"), ("end", "<f8")], align=True
)

#: ctypes struct -> the numpy record with its layout.
RECORD_DTYPES = {
    n.EntityState: ENTITY_STATE_DTYPE,
    n.GazeInfo: GAZE_INFO_DTYPE,
    n.EyeInfo: EYE_INFO_DTYPE,
    n.Constraint: CONSTRAINT_DTYPE,
}

#: Floats per element of the float-only structs.
WIDTHS = {n.Vec3: 3, n.Quat: 4, n.DualQuat: 8}


def float_rows(value, ctype, name: str) -> np.ndarray:
    """``value`` as a C-contiguous float32 array of shape ``(rows, width)``, where ``width``
    is 3, 4 or 8 for ``Vec3``, ``Quat`` or ``DualQuat``. Zero-copy for a float32
    C-contiguous array whose last dimension is ``width`` (or flat, of a multiple of it) and
    for ctypes objects of ``ctype``; a copy otherwise."""
    width = WIDTHS[ctype]
    if isinstance(value, (ctypes.Array, ctypes.Structure)):
        array = np.frombuffer(value, dtype=np.float32)
    else:
        array = np.ascontiguousarray(np.asarray(value, dtype=np.float32))
    if array.ndim == 0 or array.size % width != 0:
        raise ValueError(f"{name}: expected rows of {width} floats, got shape {array.shape}")
    if array.ndim > 1 and array.shape[-1] != width:
        raise ValueError(f"{name}: expected a last dimension of {width}, got {array.shape}")
    return array.reshape(-1, width)


def float_values(value, name: str) -> np.ndarray:
    """``value`` as a C-contiguous 1-D float32 array (zero-copy when it already is one)."""
    array = np.ascontiguousarray(np.asarray(value, dtype=np.float32))
    if array.ndim != 1:
        array = array.reshape(-1)
    return array


def pointer(array: np.ndarray, ctype):
    """A ``POINTER(ctype)`` to the first element of ``array`` (kept alive by the caller)."""
    return array.ctypes.data_as(POINTER(ctype))


class FloatOut:
    """An output of ``rows x width`` floats: the caller's ``out`` (a numpy array of at least
    that many floats) written in place when it is float32, C-contiguous and writeable, else
    a temporary copied into ``out`` by ``result()``. Without ``out``, a new array of
    ``shape`` (default ``(rows, width)``)."""

    def __init__(self, out, rows: int, width: int, name: str, shape=None):
        self.out = out
        count = rows * width
        if out is None:
            self.buffer = np.empty(shape if shape is not None else (rows, width), np.float32)
            self.in_place = True
            return
        if not isinstance(out, np.ndarray):
            raise TypeError(f"{name}: out must be a numpy array")
        if out.size < count:
            raise ValueError(f"{name}: out holds {out.size} floats, {count} needed")
        self.in_place = out.dtype == np.float32 and out.flags.c_contiguous and out.flags.writeable
        if self.in_place:
            self.buffer = out.reshape(-1)[:count]
        else:
            self.buffer = np.empty(count, dtype=np.float32)

    def result(self):
        if self.out is None:
            return self.buffer
        if not self.in_place:
            self.out.flat[: self.buffer.size] = self.buffer.reshape(-1)
        return self.out


def records_in(value, ctype, name: str):
    """``value`` as something C can read as ``count`` consecutive ``ctype`` structs:
    returns ``(keep_alive, pointer, count)``. Zero-copy for a ctypes array of ``ctype`` and
    for a C-contiguous numpy array of the matching record dtype; a sequence of ``ctype``
    structs, or a numpy record array with the same field names, is copied."""
    dtype = RECORD_DTYPES[ctype]
    if isinstance(value, ctypes.Array) and value._type_ is ctype:
        return value, ctypes.cast(value, POINTER(ctype)), len(value)
    if isinstance(value, np.ndarray) and value.dtype.names is not None:
        if value.dtype == dtype and value.flags.c_contiguous:
            array = value.reshape(-1)
        else:
            array = np.zeros(value.size, dtype=dtype)
            for field in dtype.names:
                if field in value.dtype.names:
                    array[field] = value.reshape(-1)[field]
                elif field == "struct_size":
                    array[field] = ctypes.sizeof(ctype)
                else:
                    raise ValueError(f"{name}: record field {field!r} missing")
        return array, pointer(array, ctype), array.size
    items = list(value)
    if not all(isinstance(item, ctype) for item in items):
        raise TypeError(
            f"{name}: expected a numpy array of {ctype.__name__} records, a ctypes array, "
            f"or a sequence of {ctype.__name__}"
        )
    array = (ctype * len(items))(*items)
    return array, ctypes.cast(array, POINTER(ctype)), len(items)


class RecordsOut:
    """An output of ``rows`` records: the caller's ``out`` (a numpy array of the record
    dtype) written in place when it fits, else a temporary copied into it."""

    def __init__(self, out, rows: int, ctype, name: str):
        self.dtype = RECORD_DTYPES[ctype]
        self.out = out
        if out is None:
            self.buffer = np.zeros(rows, dtype=self.dtype)
            self.in_place = True
            return
        if not isinstance(out, np.ndarray) or out.dtype.names is None:
            raise TypeError(f"{name}: out must be a numpy record array")
        if out.size < rows:
            raise ValueError(f"{name}: out holds {out.size} records, {rows} needed")
        self.in_place = out.dtype == self.dtype and out.flags.c_contiguous and out.ndim == 1
        self.buffer = out[:rows] if self.in_place else np.zeros(rows, dtype=self.dtype)

    def result(self, written: int | None = None):
        if self.out is None:
            return self.buffer if written is None else self.buffer[:written]
        if not self.in_place:
            count = self.buffer.size if written is None else written
            for field in self.dtype.names:
                if field in self.out.dtype.names:
                    self.out[field][:count] = self.buffer[field][:count]
        return self.out if written is None else self.out[:written]


def vec3(value, name: str) -> n.Vec3:
    """A ``Vec3`` from three numbers (a tuple, a numpy array, a ``Vec3``)."""
    if isinstance(value, n.Vec3):
        return value
    x, y, z = (float(c) for c in np.asarray(value, dtype=np.float64).reshape(-1))
    return n.Vec3(x, y, z)


def quat(value, name: str) -> n.Quat:
    """A ``Quat`` from four numbers x, y, z, w."""
    if isinstance(value, n.Quat):
        return value
    x, y, z, w = (float(c) for c in np.asarray(value, dtype=np.float64).reshape(-1))
    return n.Quat(x, y, z, w)
