"""``crowdgaze.Rig``: a skeleton mapped to a gaze chain (the ``cg_rig`` handle).

A rig reads a skeleton at rest (bone names, parents, translations and rotations relative
to each parent) and finds which bones are the spine, the neck, the head and the eyes, by
name, the way importers write them (Mixamo, Unreal, Unity and VRM, Daz, Character Creator,
Rigify, BVH, ...); ``bone_map`` overrides what the names say. It then gives the gaze chain
to add the character with (``Rig.chain``) and, each frame, converts the engine's bone local
rotations to the crowd's base pose (``Rig.base_pose``, for ``Crowd.set_base_pose``) and the
crowd's joints back to bone local rotations (``Rig.write_joints``, from
``Crowd.read_joints``).

A rig is immutable: every method may run on several threads at once. Arguments are
checked before any C call, as everywhere in the package (``crowdgaze._checks``,
``crowdgaze._arrays``).
"""

from __future__ import annotations

import ctypes
import operator
from collections.abc import Iterable, Mapping
from ctypes import POINTER, byref, c_char_p, c_int32, c_uint32, sizeof
from typing import Any, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _arrays as a
from . import _checks as c
from . import _exceptions as e
from . import _native as n
from ._errors import check
from ._library import lib
from ._owner import HandleOwner
from .crowd import Crowd

#: What ``Rig``'s ``bone_map`` takes: ``"Name=role,..."``, or ``{name: role}`` with each
#: role a ``BoneRole`` (or its value) or a role name (``"spine"``, ``"left_eye"``, ...).
BoneMapLike = Union[str, Mapping[str, Union[int, str]]]

_AXES = {int(axis) for axis in n.Axis}


def _names(value: Any, where: str) -> list[bytes]:
    """The bone names as UTF-8, each a ``str`` without NUL."""
    if isinstance(value, (str, bytes, bytearray, memoryview)) or not isinstance(
        value, Iterable
    ):
        raise e.type_error(
            f"{where}: names must be a sequence of str (one per bone), got "
            f"{c.describe(value)} ({type(value).__name__})"
        )
    names = [c.text(name, where, f"names[{index}]") for index, name in enumerate(value)]
    if not names:
        raise e.value_error(f"{where}: names is empty: a skeleton has at least one bone")
    if len(names) > n.CG_MAX_RIG_BONES:
        raise e.range_error(
            f"{where}: names holds {len(names)} bones, at most {n.CG_MAX_RIG_BONES} "
            f"(CG_MAX_RIG_BONES)"
        )
    return names


def _parent(value: Any, where: str, index: int) -> int:
    """One parent index: an integer, or None for none (-1)."""
    if value is None:
        return -1
    if isinstance(value, (bool, np.bool_)):
        raise e.type_error(f"{where}: parents[{index}] must be an integer or None, got a bool")
    try:
        return operator.index(value)
    except TypeError:
        raise e.type_error(
            f"{where}: parents[{index}] must be an integer or None, got {c.describe(value)} "
            f"({type(value).__name__})"
        ) from None


def _parents(value: Any, count: int, where: str) -> NDArray[np.int32]:
    """The parent of each bone as an ``int32`` array (-1: none), each -1 or a bone."""
    if value is None or isinstance(value, (str, bytes, bytearray, memoryview, dict, set)):
        raise e.type_error(
            f"{where}: parents must be integers (-1 or None for a bone without parent), got "
            f"{c.describe(value)} ({type(value).__name__})"
        )
    if isinstance(value, np.ndarray) and value.dtype.kind != "O":
        if value.dtype.kind not in "iu":
            raise e.type_error(
                f"{where}: parents must be integers, got an array of dtype {value.dtype}"
            )
        if value.ndim != 1:
            raise e.value_error(
                f"{where}: parents must be one integer per bone, got shape {value.shape}"
            )
        array = value.astype(np.int64)
    else:
        if not isinstance(value, Iterable):
            raise e.type_error(
                f"{where}: parents must be a sequence of integers, got {c.describe(value)} "
                f"({type(value).__name__})"
            )
        array = np.array(
            [_parent(item, where, index) for index, item in enumerate(value)], dtype=np.int64
        )
    if array.size != count:
        raise e.value_error(
            f"{where}: parents holds {array.size} parents for {count} names (one per bone)"
        )
    bad = np.flatnonzero((array < -1) | (array >= count))
    if bad.size:
        index = int(bad[0])
        raise e.range_error(
            f"{where}: parents[{index}] is {int(array[index])}: a parent is -1 (or None: no "
            f"parent) or the index of one of the {count} bones"
        )
    return np.ascontiguousarray(array, dtype=np.int32)


def _rows(value: Any, ctype: Any, count: int, where: str, name: str) -> np.ndarray:
    """``value`` as ``count`` rows of 3 or 4 float32 (``(count, 3)`` or ``(count, 4)``)."""
    rows = a.float_rows(value, ctype, where, name)
    if len(rows) != count:
        raise e.value_error(
            f"{where}: {name} holds {len(rows)} rows for {count} bones, must have the shape "
            f"({count}, {a.WIDTHS[ctype]})"
        )
    return rows


def _axis(value: Any, where: str, name: str) -> int:
    """A ``cg_axis``, or ``CG_RIG_AXIS_DETECT`` for None."""
    if value is None:
        return n.CG_RIG_AXIS_DETECT
    axis = c.integer(value, where, name)
    if axis not in _AXES:
        raise e.range_error(
            f"{where}: {name} must be a crowdgaze.Axis (0..5) or None (detected), got {axis}"
        )
    return axis


def _role_text(role: Any, where: str, name: str) -> str:
    """A role of a ``bone_map`` dict as the C parser reads it."""
    if isinstance(role, str):
        text = role
    else:
        value = c.integer(role, where, f"bone_map[{name!r}]")
        try:
            text = n.BoneRole(value).name.lower()
        except ValueError:
            raise e.range_error(
                f"{where}: bone_map[{name!r}] is {value}, not a crowdgaze.BoneRole (0..6)"
            ) from None
    c.text(text, where, f"bone_map[{name!r}]")
    if not text.strip() or "," in text or "=" in text:
        raise e.value_error(
            f"{where}: bone_map[{name!r}] is {text!r}, not a role (root, spine, neck, head, "
            f"left_eye, right_eye or none)"
        )
    return text


def bone_map_text(value: Any, where: str = "bone_map_text") -> bytes | None:
    """``bone_map`` as the ``"Name=role,..."`` UTF-8 string ``cg_rig_desc.bone_map`` takes
    (None for None): a str is checked and kept; a mapping ``{name: role}`` is written out,
    each role a ``BoneRole`` (or its value) or a role name."""
    if value is None:
        return None
    if isinstance(value, str):
        return c.text(value, where, "bone_map")
    if not isinstance(value, Mapping):
        raise e.type_error(
            f"{where}: bone_map must be a str ('Name=role,...'), a dict {{name: role}} or "
            f"None, got {c.describe(value)} ({type(value).__name__})"
        )
    entries = []
    for name, role in value.items():
        c.text(name, where, f"bone_map key {c.describe(name)}")
        if not name.strip() or "," in name or "=" in name:
            raise e.value_error(
                f"{where}: bone_map key {name!r} is not a bone name a bone map can hold "
                f"(empty, or with ',' or '=')"
            )
        entries.append(f"{name}={_role_text(role, where, name)}")
    return ",".join(entries).encode("utf-8")


def _crowd_config(value: Any, where: str) -> n.CrowdConfig | None:
    if value is None:
        return None
    if isinstance(value, Crowd):
        return value.config
    if isinstance(value, n.CrowdConfig):
        return value
    raise e.type_error(
        f"{where}: crowd must be a crowdgaze.Crowd, a crowdgaze.CrowdConfig or None, got "
        f"{c.describe(value)} ({type(value).__name__})"
    )


def _count(handle: Any, function: Any, name: str) -> int:
    out = c_uint32()
    check(function(handle, byref(out)), name)
    return out.value


class Rig(HandleOwner):
    """A skeleton mapped to a gaze chain.

    ``Rig(names, parents, translations, rotations=None, *, units_per_metre=1.0, up=None,
    forward=None, bone_map=None, crowd=None)``:

    - ``names``: one ``str`` per bone (unique, without NUL);
    - ``parents``: each bone's parent index, -1 or None for none, parents before children
      (integers, or an integer array);
    - ``translations``: ``(bones, 3)`` rest offsets from the parent, in the parent's frame,
      in the skeleton's units;
    - ``rotations``: ``(bones, 4)`` rest rotations relative to the parent (x y z w), or None
      for identity;
    - ``units_per_metre``: the skeleton's units (100 for centimetres);
    - ``up``, ``forward``: the skeleton's ``Axis`` (up, and the way it faces), or None to
      detect them from the rest pose;
    - ``bone_map``: overrides of what the names say, ``"Name=role,..."`` or ``{name: role}``
      (roles ``root``, ``spine``, ``neck``, ``head``, ``left_eye``, ``right_eye``, ``none``,
      or ``BoneRole`` values); most shipping rigs need none;
    - ``crowd``: the ``Crowd`` (or its ``CrowdConfig``) the character goes into: the chain,
      the base poses and the joints are in its axes and units (default: Y up, +Z forward,
      metres).

    A skeleton that cannot be mapped raises ``InvalidArgumentError`` whose message names
    the bone and the override that fixes it; ``report`` says what was mapped and why.
    Release the rig with ``close()`` or a ``with`` block (or let it be collected). It
    cannot be copied or pickled; its methods may run on several threads at once.
    """

    _kind = "rig"
    _destroy: Any = lib.cg_rig_destroy

    def __init__(
        self,
        names: Iterable[str],
        parents: ArrayLike | Iterable[int | None],
        translations: a.Numbers,
        rotations: a.Numbers | None = None,
        *,
        units_per_metre: float = 1.0,
        up: int | None = None,
        forward: int | None = None,
        bone_map: BoneMapLike | None = None,
        crowd: Crowd | n.CrowdConfig | None = None,
    ):
        where = "Rig"
        self._refuse_reinit(where)
        encoded = _names(names, where)
        count = len(encoded)
        parent_array = _parents(parents, count, where)
        translation_rows = _rows(translations, n.Vec3, count, where, "translations")
        rotation_rows = (
            None if rotations is None else _rows(rotations, n.Quat, count, where, "rotations")
        )
        units = c.real(units_per_metre, where, "units_per_metre")
        up_axis = _axis(up, where, "up")
        forward_axis = _axis(forward, where, "forward")
        map_text = bone_map_text(bone_map, where)
        config = _crowd_config(crowd, where)

        desc = n.RigDesc(struct_size=sizeof(n.RigDesc))
        check(lib.cg_rig_desc_init(byref(desc)), "cg_rig_desc_init")
        name_array = (c_char_p * count)(*encoded)
        desc.bone_count = count
        desc.bone_names = ctypes.cast(name_array, POINTER(c_char_p))
        desc.parents = a.pointer(parent_array, c_int32)
        desc.rest_translations = a.pointer(translation_rows, n.Vec3)
        if rotation_rows is not None:
            desc.rest_rotations = a.pointer(rotation_rows, n.Quat)
        desc.units_per_metre = units
        desc.up = up_axis
        desc.forward = forward_axis
        desc.bone_map = map_text
        if config is not None:
            desc.crowd_up = config.up_axis
            desc.crowd_forward = config.forward_axis
            desc.crowd_units_per_metre = config.units_per_metre
        handle = POINTER(n.RigHandle)()
        check(lib.cg_rig_create(byref(desc), byref(handle)), "cg_rig_create")
        try:
            bone_count = _count(handle, lib.cg_rig_bone_count, "cg_rig_bone_count")
            joint_count = _count(handle, lib.cg_rig_joint_count, "cg_rig_joint_count")
        except BaseException:
            lib.cg_rig_destroy(handle)
            raise
        self._bone_count = bone_count
        self._joint_count = joint_count
        self._adopt(handle, where)

    def _describe(self) -> str:
        return f"{self._bone_count} bones, a chain of {self._joint_count} joints"

    # --- what was mapped ---------------------------------------------------------------------

    @property
    def chain(self) -> n.ChainDesc:
        """The gaze chain (in the crowd's axes and units), a new ``ChainDesc`` on each
        access: add the character with ``crowd.add_character(position, chain=rig.chain)``."""
        where = "Rig.chain"
        out = n.ChainDesc(struct_size=sizeof(n.ChainDesc))
        with self._call(where) as handle:
            check(lib.cg_rig_chain(handle, byref(out)), "cg_rig_chain")
        return out

    @property
    def bone_count(self) -> int:
        """The number of bones (the rows of ``base_pose``'s and ``write_joints``'
        ``bone_rotations``)."""
        with self._call("Rig.bone_count") as handle:
            return _count(handle, lib.cg_rig_bone_count, "cg_rig_bone_count")

    @property
    def joint_count(self) -> int:
        """The number of chain joints (the rows of a base pose and of the joints
        ``Crowd.read_joints`` gives for the character)."""
        with self._call("Rig.joint_count") as handle:
            return _count(handle, lib.cg_rig_joint_count, "cg_rig_joint_count")

    @property
    def chain_bones(self) -> NDArray[np.uint32]:
        """The bone of each chain joint, bottom to top (spine, neck, head, then the left and
        right eye if the chain has eyes): a ``uint32`` array of ``joint_count`` bone
        indices."""
        where = "Rig.chain_bones"
        out = np.zeros(self._joint_count, np.uint32)
        with self._call(where) as handle:
            check(
                lib.cg_rig_chain_bones(handle, a.pointer(out, c_uint32), out.size),
                "cg_rig_chain_bones",
            )
        return out

    @property
    def roles(self) -> NDArray[np.uint32]:
        """The role of each bone (``BoneRole`` values, ``NONE`` for bones outside the
        chain's roles), in the skeleton's order: a ``uint32`` array of ``bone_count``
        (``cg.BoneRole(int(rig.roles[i]))`` names one)."""
        where = "Rig.roles"
        out = np.zeros(self._bone_count, np.uint32)
        with self._call(where) as handle:
            check(
                lib.cg_rig_bone_roles(handle, a.pointer(out, c_uint32), out.size),
                "cg_rig_bone_roles",
            )
        return out

    @property
    def report(self) -> str:
        """The mapping report, one line each: the chain (joint counts, the bone it hangs
        from), the axes and how they were found, each chain bone's role and whether it came
        from its name or an override, and notes."""
        with self._call("Rig.report") as handle:
            length = lib.cg_rig_report(handle, None, 0)
            buffer = ctypes.create_string_buffer(length + 1)
            lib.cg_rig_report(handle, buffer, len(buffer))
        return buffer.value.decode("utf-8", errors="replace")

    # --- each frame ------------------------------------------------------------------------

    def base_pose(self, bone_rotations: a.Numbers, out: a.Out = None) -> NDArray[np.float32]:
        """The crowd's base pose from the engine's bone local rotations: ``bone_rotations``
        is ``(bone_count, 4)`` (x y z w, each relative to its parent, the skeleton's order);
        returns ``(joint_count, 4)`` float32 for ``Crowd.set_base_pose``, or writes ``out``
        (exactly that) in place. A NaN or infinite rotation the chain reads raises
        ``NonFiniteError``."""
        where = "Rig.base_pose"
        bones = a.float_rows(bone_rotations, n.Quat, where, "bone_rotations")
        if out is not None:
            a.check_out(out, a.FLOAT32, where, ndim=2)
        if len(bones) != self._bone_count:
            raise e.value_error(
                f"{where}: bone_rotations holds {len(bones)} rotations, the rig "
                f"{self._bone_count} bones: it must have the shape ({self._bone_count}, 4)"
            )
        out = a.shaped(out, a.FLOAT32, (self._joint_count, 4), where)
        if np.shares_memory(out, bones):
            raise e.value_error(f"{where}: out overlaps bone_rotations")
        with self._call(where) as handle:
            check(
                lib.cg_rig_base_pose(
                    handle, a.pointer(bones, n.Quat), len(bones), a.pointer(out, n.Quat),
                    len(out),
                ),
                "cg_rig_base_pose",
            )
        return out

    def write_joints(
        self, joints: a.Numbers, bone_rotations: NDArray[np.float32]
    ) -> NDArray[np.float32]:
        """Writes the crowd's joints (``(joint_count, 4)``, as ``Crowd.read_joints(row, 1)``
        gives them for the character) into ``bone_rotations``, the engine's bone local
        rotations, in place, and returns it: each chain joint's bone gets the rotation that,
        with the bones above it as they are in ``bone_rotations``, makes the joint's; other
        bones are left alone. ``bone_rotations`` follows the rule of every ``out=``: a
        writeable, C-contiguous float32 numpy array of exactly ``(bone_count, 4)``. On an
        error nothing is written."""
        where = "Rig.write_joints"
        quats = a.float_rows(joints, n.Quat, where, "joints")
        name = "bone_rotations"
        a.check_out(bone_rotations, a.FLOAT32, where, ndim=2, name=name)
        a.check_shape(bone_rotations, (self._bone_count, 4), where, name=name)
        if len(quats) != self._joint_count:
            raise e.value_error(
                f"{where}: joints holds {len(quats)} rotations, the rig's chain "
                f"{self._joint_count} joints: it must have the shape ({self._joint_count}, 4)"
            )
        if np.shares_memory(quats, bone_rotations):
            raise e.value_error(f"{where}: joints overlaps bone_rotations")
        with self._call(where) as handle:
            check(
                lib.cg_rig_write_joints(
                    handle, a.pointer(quats, n.Quat), len(quats),
                    a.pointer(bone_rotations, n.Quat), len(bone_rotations),
                ),
                "cg_rig_write_joints",
            )
        return bone_rotations
