"""numpy views of the C arrays: float rows (quaternions ``(n, 4)``, dual quaternions
``(n, 8)``, vectors ``(n, 3)``) and structured arrays laid out exactly as the C structs; and
the checked conversion of every array, vector and struct-field argument.

Inputs: an input whose layout already fits (C-contiguous, aligned, the right dtype and last
dimension), or a ctypes array or struct of the expected type, is passed to C as it is,
without a copy. Any other array of numbers (numpy arrays of integers or floats, nested
sequences of real numbers, ctypes arrays of ``c_double`` or ``c_int``, ``memoryview`` and
``array.array`` of numbers) is converted by value (one copy). Strings, raw bytes
(``bytes``, ``bytearray``, byte memoryviews), booleans, complex numbers, dicts, sets and
ctypes arrays of another struct are refused with ``TypeError``; a finite value too large
for a C float with ``OverflowError``.

Outputs: an ``out=`` argument must be a writeable, C-contiguous, aligned numpy array of the
exact dtype and shape of the result; it is written in place (only when the call succeeds).
Anything else raises ``TypeError`` (not a numpy array, another dtype) or ``ValueError``
(shape, read-only, layout), naming ``out``: a result is never converted or truncated.
"""

from __future__ import annotations

import ctypes
from collections.abc import Sequence
from typing import Any, Optional, Union
from ctypes import POINTER, c_char_p, c_double, c_float, c_uint32, c_uint64

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _checks as c
from . import _exceptions as e
from . import _native as n

#: What number arguments take (checked at run time, see above): numpy arrays, nested
#: sequences, ctypes structs and arrays of the matching type.
Numbers = Union[ArrayLike, ctypes.Structure, "ctypes.Array[Any]"]
#: What the ``out=`` arguments take: None (a new array) or a numpy array of the result's
#: exact dtype and shape.
Out = Optional[NDArray[Any]]

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

#: ``cg_eyelids`` as a numpy record: ``left_closure`` and ``right_closure`` from 0 (open)
#: to 1 (closed), ``left_lid_pitch`` and ``right_lid_pitch`` in radians.
EYELIDS_DTYPE = np.dtype(
    [
        ("character", "<u4"),
        ("left_closure", "<f4"),
        ("right_closure", "<f4"),
        ("left_lid_pitch", "<f4"),
        ("right_lid_pitch", "<f4"),
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
    n.Eyelids: EYELIDS_DTYPE,
    n.Constraint: CONSTRAINT_DTYPE,
}

#: Floats per element of the float-only structs.
WIDTHS = {n.Vec3: 3, n.Quat: 4, n.DualQuat: 8}

#: ctypes struct -> its C name, for messages.
C_NAMES = {ctype: name for name, ctype in n.STRUCTS.items()}

_DTYPE_NAMES = {
    np.dtype(np.float32): "float32",
    ENTITY_STATE_DTYPE: "crowdgaze.ENTITY_STATE_DTYPE",
    GAZE_INFO_DTYPE: "crowdgaze.GAZE_INFO_DTYPE",
    EYE_INFO_DTYPE: "crowdgaze.EYE_INFO_DTYPE",
    EYELIDS_DTYPE: "crowdgaze.EYELIDS_DTYPE",
    CONSTRAINT_DTYPE: "crowdgaze.CONSTRAINT_DTYPE",
}

_NOT_NUMBERS = (str, bytes, bytearray, dict, set, frozenset, bool, np.bool_, complex)


def _what(value) -> str:
    """``value`` for a message: ``a ctypes array of Quat``, ``an array of dtype int32``,
    ``{} (dict)``."""
    if isinstance(value, ctypes.Array):
        element = value._type_
        return f"a ctypes array of {getattr(element, '__name__', element)}"
    if isinstance(value, np.ndarray):
        return f"an array of dtype {value.dtype} and shape {value.shape}"
    return f"{c.describe(value)} ({type(value).__name__})"


def numbers(value, where: str, name: str) -> np.ndarray:
    """``value`` as a numpy array of integers or floats (not yet converted to float32),
    refusing anything that is not numbers (see the module's doc)."""
    if value is None or isinstance(value, _NOT_NUMBERS):
        raise e.type_error(
            f"{where}: {name} must be real numbers (a numpy array or a sequence), "
            f"got {_what(value)}"
        )
    if isinstance(value, memoryview) and value.format in ("B", "b", "c"):
        raise e.type_error(
            f"{where}: {name} is raw bytes (a memoryview of format {value.format!r}); "
            f"reinterpret them explicitly, e.g. with numpy.frombuffer(..., numpy.float32)"
        )
    try:
        array = np.asarray(value)
    except Exception as error:
        raise e.type_error(f"{where}: {name} must be real numbers: {error}") from error
    kind = array.dtype.kind
    if kind == "O":
        if array.ndim == 0:
            raise e.type_error(f"{where}: {name} must be real numbers, got {_what(value)}")
        items = [c.real(x, where, f"{name} element", single=False) for x in array.reshape(-1)]
        array = np.array(items, dtype=np.float64).reshape(array.shape)
    elif kind not in "fiu":
        raise e.type_error(
            f"{where}: {name} must be real numbers, got {_what(value)}, read as dtype "
            f"{array.dtype}"
        )
    return array


def float32(array: np.ndarray, where: str, name: str) -> np.ndarray:
    """A numeric ``array`` as a C-contiguous, aligned float32 array (itself if it is one);
    ``OverflowError`` for finite values too large for a C float."""
    if array.dtype == np.float32:
        return np.require(array, np.float32, ["C", "A"])
    with np.errstate(over="ignore", invalid="ignore"):
        result = np.require(array.astype(np.float32), np.float32, ["C", "A"])
    if array.dtype.kind == "f" and array.dtype.itemsize > 4 and np.isinf(result).any():
        overflowed = np.isinf(result) & np.isfinite(array.reshape(result.shape))
        if overflowed.any():
            raise e.range_error(
                f"{where}: {name} holds {array.reshape(-1)[overflowed.reshape(-1)][0]!r}, "
                f"out of the range of a C float (at most {c.FLOAT32_MAX:g} in magnitude)"
            )
    return result


def _is_floats_of(value, ctype) -> bool:
    """Whether the ctypes object ``value`` is a ``ctype`` or an array (of arrays) of
    ``ctype`` or of ``c_float``: memory C can read as float rows as it is."""
    if isinstance(value, ctypes.Structure):
        return isinstance(value, ctype)
    element: Any = type(value)
    while issubclass(element, ctypes.Array):
        element = element._type_
    return element is ctype or element is c_float


def float_rows(value, ctype, where: str, name: str) -> np.ndarray:
    """``value`` as a C-contiguous float32 array of shape ``(rows, width)``, where ``width``
    is 3, 4 or 8 for ``Vec3``, ``Quat`` or ``DualQuat``. Zero-copy for a float32
    C-contiguous aligned array whose last dimension is ``width`` (or flat, of a multiple of
    it) and for ctypes objects of ``ctype`` or ``c_float``; converted by value otherwise."""
    width = WIDTHS[ctype]
    if isinstance(value, (ctypes.Array, ctypes.Structure)) and _is_floats_of(value, ctype):
        array = np.frombuffer(value, dtype=np.float32)  # type: ignore[call-overload]
    elif isinstance(value, ctypes.Structure):
        raise e.type_error(
            f"{where}: {name} must be a crowdgaze.{ctype.__name__} or real numbers, "
            f"got {_what(value)}"
        )
    else:
        array = float32(numbers(value, where, name), where, name)
    if array.ndim == 0 or array.size % width != 0:
        raise e.value_error(
            f"{where}: {name} must be rows of {width} numbers ({ctype.__name__}), "
            f"got shape {array.shape}"
        )
    if array.ndim > 1 and array.shape[-1] != width:
        raise e.value_error(
            f"{where}: {name} must have a last dimension of {width} ({ctype.__name__}), "
            f"got shape {array.shape}"
        )
    return array.reshape(-1, width)


def float_values(value, where: str, name: str) -> np.ndarray:
    """``value`` as a C-contiguous 1-D float32 array (zero-copy when it already is one)."""
    return float32(numbers(value, where, name), where, name).reshape(-1)


def fixed_floats(value, count: int, where: str, name: str, shapes=None) -> np.ndarray:
    """Exactly ``count`` numbers as a C-contiguous float32 array of ``count``; ``shapes``
    lists the shapes accepted (default: any holding ``count`` numbers)."""
    array = numbers(value, where, name)
    if array.size != count or (shapes is not None and array.shape not in shapes):
        accepted = " or ".join(str(s) for s in shapes) if shapes else f"{count} numbers"
        raise e.value_error(f"{where}: {name} must be {accepted}, got shape {array.shape}")
    return float32(array, where, name)


def unsigned(value, where: str, name: str, ctype: str = "uint32") -> np.ndarray:
    """``value`` (an integer or integers) as a C-contiguous 1-D ``uint32`` (or ``uint64``)
    array, each checked in range: booleans and floats are refused, as for one integer."""
    if value is None or isinstance(value, _NOT_NUMBERS) or isinstance(value, memoryview):
        raise e.type_error(f"{where}: {name} must be integers, got {_what(value)}")
    try:
        array = np.asarray(value)
    except Exception as error:
        raise e.type_error(f"{where}: {name} must be integers: {error}") from error
    dtype = np.uint32 if ctype == "uint32" else np.uint64
    if array.dtype.kind == "O":
        items = [c.integer(item, where, f"{name} element", ctype) for item in array.reshape(-1)]
        return np.array(items, dtype=dtype)
    # An empty list reads as float64: it holds no value that is not an integer.
    if array.dtype.kind not in "iu" and not (array.size == 0 and array.dtype.kind == "f"):
        raise e.type_error(
            f"{where}: {name} must be integers, got {_what(value)}, read as dtype {array.dtype}"
        )
    array = array.reshape(-1)
    if array.size:
        low, high = int(array.min()), int(array.max())
        largest = c.UNSIGNED[ctype]
        if low < 0 or high > largest:
            bad = low if low < 0 else high
            raise e.range_error(
                f"{where}: {name} must be integers in 0..{largest} ({ctype}), holds {bad}"
            )
    return np.ascontiguousarray(array, dtype=dtype)


def pointer(array: np.ndarray, ctype):
    """A ``POINTER(ctype)`` to the first element of ``array`` (kept alive by the caller)."""
    return array.ctypes.data_as(POINTER(ctype))


# --- outputs --------------------------------------------------------------------------------


#: float32, the dtype of every float output.
FLOAT32 = np.dtype(np.float32)


def check_out(
    out, dtype: np.dtype, where: str, ndim: int | None = None, name: str = "out"
) -> np.ndarray:
    """Refuses an ``out`` that is not a writeable, C-contiguous, aligned numpy array of
    ``dtype`` (and ``ndim`` dimensions); its shape is checked by ``check_shape``. ``name``
    is the argument's, for an array written in place that is not called ``out``."""
    if not isinstance(out, np.ndarray):
        raise e.type_error(
            f"{where}: {name} must be a numpy array of {_DTYPE_NAMES.get(dtype, dtype)}, "
            f"got {_what(out)}"
        )
    if out.dtype != dtype:
        shown = out.dtype if out.dtype.names is None else "another record dtype"
        raise e.type_error(
            f"{where}: {name} must have the dtype {_DTYPE_NAMES.get(dtype, dtype)}, got "
            f"{shown} (results are never converted)"
        )
    if ndim is not None and out.ndim != ndim:
        raise e.value_error(
            f"{where}: {name} must have {ndim} dimension(s), got shape {out.shape}"
        )
    flags = out.flags
    if not flags.writeable:
        raise e.value_error(f"{where}: {name} is read-only")
    if not flags.c_contiguous:
        raise e.value_error(f"{where}: {name} must be C-contiguous (a strided view is not)")
    if not flags.aligned:
        raise e.value_error(f"{where}: {name} is not aligned for its dtype")
    return out


def check_shape(out: np.ndarray, shape: tuple, where: str, name: str = "out") -> np.ndarray:
    """Refuses an ``out`` whose shape is not exactly ``shape``."""
    if out.shape != shape:
        raise e.value_error(f"{where}: {name} must have the shape {shape}, got {out.shape}")
    return out


def output(out, dtype: np.dtype, shape: tuple, where: str) -> np.ndarray:
    """``out`` checked (dtype, layout, exact shape), or a new array if ``out`` is None."""
    if out is None:
        return np.empty(shape, dtype)
    return check_shape(check_out(out, dtype, where, len(shape)), shape, where)


def shaped(out, dtype: np.dtype, shape: tuple, where: str) -> np.ndarray:
    """An ``out`` already through ``check_out``, its shape checked; or a new array."""
    if out is None:
        return np.empty(shape, dtype)
    return check_shape(out, shape, where)


# --- records --------------------------------------------------------------------------------


def _record_field(array, field, source, where, name):
    """Copies field ``field`` of the records ``source`` into ``array``, checked."""
    target = array[field]
    label = f"{name}[{field!r}]"
    if source.shape != target.shape:
        raise e.value_error(
            f"{where}: {label} must have the shape {target.shape}, got {source.shape}"
        )
    kind = source.dtype.kind
    if target.dtype.kind == "u":
        if kind not in "iu":
            raise e.type_error(f"{where}: {label} must be integers, got dtype {source.dtype}")
        if source.size and (int(source.min()) < 0 or int(source.max()) > c.UNSIGNED["uint32"]):
            raise e.range_error(f"{where}: {label} must be integers in 0..{2**32 - 1}")
        array[field] = source
    else:
        if kind not in "fiu":
            raise e.type_error(f"{where}: {label} must be real numbers, got dtype {source.dtype}")
        array[field] = float32(np.asarray(source), where, label)


def records_in(value, ctype, where: str, name: str):
    """``value`` as something C can read as ``count`` consecutive ``ctype`` structs:
    returns ``(keep_alive, pointer, count)``. Zero-copy for a ``ctype``, a ctypes array of
    ``ctype`` and a C-contiguous aligned numpy array of the matching record dtype; a
    sequence of ``ctype`` structs, or a numpy record array with the same field names
    (integers and reals checked as they are converted), is copied."""
    dtype = RECORD_DTYPES[ctype]
    if isinstance(value, ctype):
        return value, ctypes.pointer(value), 1
    if isinstance(value, ctypes.Array):
        if value._type_ is not ctype:
            raise e.type_error(
                f"{where}: {name} must hold {ctype.__name__} structs, got {_what(value)}"
            )
        return value, ctypes.cast(value, POINTER(ctype)), len(value)
    if isinstance(value, np.ndarray):
        if value.dtype.names is None:
            raise e.type_error(
                f"{where}: {name} must be a record array of {_DTYPE_NAMES[dtype]} (see "
                f"crowdgaze.entity_states), got {_what(value)}"
            )
        flat = value.reshape(-1)
        if value.dtype == dtype:
            array = np.require(flat, dtype, ["C", "A"])
        else:
            array = np.zeros(flat.size, dtype=dtype)
            for field in dtype.names or ():
                if field in flat.dtype.names:
                    _record_field(array, field, flat[field], where, name)
                elif field == "struct_size":
                    array[field] = ctypes.sizeof(ctype)
                else:
                    raise e.value_error(f"{where}: {name} has no record field {field!r}")
        return array, pointer(array, ctype), array.size
    if isinstance(value, (str, bytes, bytearray, memoryview)) or not isinstance(
        value, Sequence
    ):
        raise e.type_error(
            f"{where}: {name} must be a numpy array of {ctype.__name__} records, a ctypes "
            f"array or a sequence (list, tuple) of {ctype.__name__}, got {_what(value)}"
        )
    items = list(value)
    for index, item in enumerate(items):
        if not isinstance(item, ctype):
            raise e.type_error(
                f"{where}: {name}[{index}] must be a crowdgaze.{ctype.__name__}, "
                f"got {_what(item)}"
            )
    array = (ctype * len(items))(*items)
    return array, ctypes.cast(array, POINTER(ctype)), len(items)


# --- vectors, quaternions and struct fields ----------------------------------------------


def _struct_of_floats(value, ctype, where: str, name: str):
    if isinstance(value, ctype):
        return value
    if isinstance(value, ctypes.Structure):
        raise e.type_error(
            f"{where}: {name} must be a crowdgaze.{ctype.__name__} or {WIDTHS[ctype]} real "
            f"numbers, got {_what(value)}"
        )
    array = fixed_floats(value, WIDTHS[ctype], where, name)
    return ctype(*(float(x) for x in array.reshape(-1)))


def vec3(value, where: str, name: str) -> n.Vec3:
    """A ``Vec3`` from three real numbers (a tuple, a numpy array, a ``Vec3``)."""
    return _struct_of_floats(value, n.Vec3, where, name)


def quat(value, where: str, name: str) -> n.Quat:
    """A ``Quat`` from four real numbers x, y, z, w (or a ``Quat``)."""
    return _struct_of_floats(value, n.Quat, where, name)


def field_value(field_type, value, where: str, name: str):
    """``value`` checked and converted for a struct field of the ctypes type
    ``field_type`` (what ``CheckedStructure`` assignments and ``struct_fields`` use)."""
    if field_type is c_uint32:
        return c.integer(value, where, name, "uint32")
    if field_type is c_uint64:
        return c.integer(value, where, name, "uint64")
    if field_type is c_float:
        return c.real(value, where, name)
    if field_type is c_double:
        return c.real(value, where, name, single=False)
    if field_type in (n.Vec3, n.Quat):
        return _struct_of_floats(value, field_type, where, name)
    if field_type is c_char_p:  # a C string: None, or a str (or UTF-8 bytes) without NUL
        if isinstance(value, bytes):
            return c.text(value.decode("utf-8", errors="surrogateescape"), where, name)
        return None if value is None else c.text(value, where, name)
    if issubclass(field_type, ctypes._Pointer):
        target = field_type._type_
        if value is None:
            return field_type()
        if isinstance(value, target):
            return ctypes.pointer(value)
        if isinstance(value, field_type):
            return value
        raise e.type_error(
            f"{where}: {name} must be a crowdgaze.{target.__name__} or None, got {_what(value)}"
        )
    return c.instance(value, field_type, where, name)


def struct_fields(ctype, fields: dict, where: str) -> list:
    """``fields`` (name -> value) checked and converted for the struct ``ctype``: a list of
    ``(name, value)`` that ``fill`` sets. Raises before anything is set."""
    types = dict(ctype._fields_)
    converted = []
    for name, value in fields.items():
        if name not in types:
            raise e.type_error(f"{where}: {C_NAMES[ctype]} has no field {name!r}")
        converted.append((name, field_value(types[name], value, where, name)))
    return converted


def fill(struct, converted: list):
    """Sets the fields ``struct_fields`` converted; returns ``struct``."""
    for name, value in converted:
        setattr(struct, name, value)
    return struct
