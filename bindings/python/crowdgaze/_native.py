"""The C ABI of crowdgaze seen from ctypes: the constants, enums and structs of
``include/crowdgaze.h`` (same names, order and types), the search for the shared library,
and every function's ``argtypes``/``restype``.

Nothing here wraps or checks: that is ``crowdgaze.crowd`` and ``crowdgaze.blend``.
"""

from __future__ import annotations

import ctypes
import enum
import os
import sys
from typing import Any
from ctypes import (
    POINTER,
    Structure,
    c_bool,
    c_char_p,
    c_double,
    c_float,
    c_int32,
    c_size_t,
    c_uint32,
    c_uint64,
)
from pathlib import Path

import numpy as np

# --- constants (#define in the header) ---------------------------------------------------

CG_NO_TARGET = 0xFFFFFFFF
CG_MAX_CONVERSATION_MEMBERS = 8
CG_MAX_CHAIN_JOINTS = 15
CG_EYE_MOTION_PAPER = 0
CG_EYE_MOTION_MAIN_SEQUENCE = 1
CG_GAZE_TARGET_POINT = 0
CG_GAZE_TARGET_ENTITY = 1
CG_GAZE_PRIORITY_OVERRIDE = 0
CG_GAZE_PRIORITY_WHEN_IDLE = 1
CG_VERSION_MAJOR = 0
CG_VERSION_MINOR = 2
CG_VERSION_PATCH = 0
#: The most bones a rig's skeleton may have (``cg_rig_desc.bone_count``).
CG_MAX_RIG_BONES = 65536
#: ``cg_rig_desc.up`` and ``forward``: detect the axis from the rest pose (the default).
CG_RIG_AXIS_DETECT = 0xFFFFFFFF
#: The identity quaternion (x, y, z, w), as a tuple any quaternion argument takes.
cg_quat_IDENTITY = (0.0, 0.0, 0.0, 1.0)


# --- enums ---------------------------------------------------------------------------------


class Status(enum.IntEnum):
    """``cg_status``: the result of every fallible call."""

    OK = 0
    NULL_ARGUMENT = 1
    INVALID_ARGUMENT = 2
    NON_FINITE = 3
    NOT_FOUND = 4
    CAPACITY = 5
    BAD_STRUCT_SIZE = 6
    WRONG_STATE = 7
    NOT_CONVERGED = 8
    INTERNAL = 9
    OUT_OF_MEMORY = 10
    POISONED = 11


class Axis(enum.IntEnum):
    """``cg_axis``: a signed world axis."""

    POSITIVE_X = 0
    NEGATIVE_X = 1
    POSITIVE_Y = 2
    NEGATIVE_Y = 3
    POSITIVE_Z = 4
    NEGATIVE_Z = 5


class JointRole(enum.IntEnum):
    """``cg_joint_role``: what a gaze chain joint is."""

    SPINE = 0
    CERVICAL = 1
    HEAD = 2
    LEFT_EYE = 3
    RIGHT_EYE = 4


class BoneRole(enum.IntEnum):
    """``cg_bone_role``: what a skeleton's bone is for the gaze chain (``Rig.roles``)."""

    #: Not part of the chain.
    NONE = 0
    #: The body root (the chain hangs from the first bone below the spine).
    ROOT = 1
    #: A spine bone (lumbar or thoracic).
    SPINE = 2
    #: A neck (cervical) bone.
    NECK = 3
    #: The head.
    HEAD = 4
    #: The character's left eye (under the head).
    LEFT_EYE = 5
    #: The character's right eye (under the head).
    RIGHT_EYE = 6


class BlendMethod(enum.IntEnum):
    """``cg_blend_method``: DLB or DIB."""

    DLB = 0
    DIB = 1


class ViewDistance(enum.IntEnum):
    """``cg_view_distance``: how the distance to a key camera is measured."""

    GEODESIC = 0
    CHORDAL = 1


class AttentionModel(enum.IntEnum):
    """``cg_attention_model``: how a character chooses where to look."""

    CROWD = 0
    SALIENCY = 1
    BASELINE = 2
    STREET = 3


class TargetPart(enum.IntEnum):
    """``cg_target_part``: which part of a target entity is looked at."""

    WHOLE = 0
    HEAD = 1
    LEFT_EYE = 2
    RIGHT_EYE = 3
    CHEST = 4
    TORSO = 5


class EyeMotion(enum.IntEnum):
    """``cg_crowd_config.eye_motion``: how the eyes time a gaze shift (the header's
    ``CG_EYE_MOTION_*`` constants, which are not a C enum)."""

    #: The paper's timing (Grillon & Thalmann 2009): the eyes arrive at half the activation
    #: time. The default.
    PAPER = CG_EYE_MOTION_PAPER
    #: The eyes' shift lasts as long as a human saccade of its amplitude (the main
    #: sequence); the head, neck and spine keep the paper's timing.
    MAIN_SEQUENCE = CG_EYE_MOTION_MAIN_SEQUENCE


class StateFlag(enum.IntFlag):
    """``cg_entity_state.flags``: the header's ``CG_STATE_*`` bits, combined with ``|``.

    They work on the ``uint32`` flags of ``ENTITY_STATE_DTYPE`` records, an element or a
    whole column at a time: ``states["flags"][i] |= cg.CG_STATE_TALKING`` sets a bit and
    ``states["flags"][i] &= ~cg.CG_STATE_TALKING`` clears it (``~`` keeps every other bit
    of the 32, so its value stays in ``0 .. 2**32 - 1``).
    """

    #: The heading is the direction of motion (``heading`` is ignored).
    HEADING_FROM_MOTION = 1
    #: ``velocity`` is given (else it is derived from the previous pushed position).
    HAS_VELOCITY = 2
    #: The entity talks in this frame (see ``Crowd.set_conversation``).
    TALKING = 4

    def __invert__(self) -> StateFlag:
        """The other bits of the 32 (not a negative number, which numpy's ``uint32``
        arrays refuse)."""
        return type(self)(~int(self) & 0xFFFFFFFF)

    def __array_ufunc__(self, ufunc: Any, method: str, *inputs: Any, **kwargs: Any) -> Any:
        # numpy takes an int subclass as an int64 array, and then refuses to write
        # `uint32_array | flag` back into a uint32 array: a flag is a uint32 to numpy.
        inputs = tuple(
            np.uint32(value) if isinstance(value, StateFlag) else value for value in inputs
        )
        return getattr(ufunc, method)(*inputs, **kwargs)


CG_STATE_HEADING_FROM_MOTION = StateFlag.HEADING_FROM_MOTION
CG_STATE_HAS_VELOCITY = StateFlag.HAS_VELOCITY
CG_STATE_TALKING = StateFlag.TALKING


#: C enum name -> Python enum, for the declaration test and for users who read the header.
ENUMS = {
    "cg_status": Status,
    "cg_axis": Axis,
    "cg_joint_role": JointRole,
    "cg_bone_role": BoneRole,
    "cg_blend_method": BlendMethod,
    "cg_view_distance": ViewDistance,
    "cg_attention_model": AttentionModel,
    "cg_target_part": TargetPart,
}

# Every enum value also under its C name (CG_STATUS_OK, CG_AXIS_POSITIVE_Y, ...), spelt out
# so that type checkers see them; tests/test_declarations.py checks them against the header.
CG_STATUS_OK = Status.OK
CG_STATUS_NULL_ARGUMENT = Status.NULL_ARGUMENT
CG_STATUS_INVALID_ARGUMENT = Status.INVALID_ARGUMENT
CG_STATUS_NON_FINITE = Status.NON_FINITE
CG_STATUS_NOT_FOUND = Status.NOT_FOUND
CG_STATUS_CAPACITY = Status.CAPACITY
CG_STATUS_BAD_STRUCT_SIZE = Status.BAD_STRUCT_SIZE
CG_STATUS_WRONG_STATE = Status.WRONG_STATE
CG_STATUS_NOT_CONVERGED = Status.NOT_CONVERGED
CG_STATUS_INTERNAL = Status.INTERNAL
CG_STATUS_OUT_OF_MEMORY = Status.OUT_OF_MEMORY
CG_STATUS_POISONED = Status.POISONED
CG_AXIS_POSITIVE_X = Axis.POSITIVE_X
CG_AXIS_NEGATIVE_X = Axis.NEGATIVE_X
CG_AXIS_POSITIVE_Y = Axis.POSITIVE_Y
CG_AXIS_NEGATIVE_Y = Axis.NEGATIVE_Y
CG_AXIS_POSITIVE_Z = Axis.POSITIVE_Z
CG_AXIS_NEGATIVE_Z = Axis.NEGATIVE_Z
CG_JOINT_ROLE_SPINE = JointRole.SPINE
CG_JOINT_ROLE_CERVICAL = JointRole.CERVICAL
CG_JOINT_ROLE_HEAD = JointRole.HEAD
CG_JOINT_ROLE_LEFT_EYE = JointRole.LEFT_EYE
CG_JOINT_ROLE_RIGHT_EYE = JointRole.RIGHT_EYE
CG_BONE_ROLE_NONE = BoneRole.NONE
CG_BONE_ROLE_ROOT = BoneRole.ROOT
CG_BONE_ROLE_SPINE = BoneRole.SPINE
CG_BONE_ROLE_NECK = BoneRole.NECK
CG_BONE_ROLE_HEAD = BoneRole.HEAD
CG_BONE_ROLE_LEFT_EYE = BoneRole.LEFT_EYE
CG_BONE_ROLE_RIGHT_EYE = BoneRole.RIGHT_EYE
CG_BLEND_METHOD_DLB = BlendMethod.DLB
CG_BLEND_METHOD_DIB = BlendMethod.DIB
CG_VIEW_DISTANCE_GEODESIC = ViewDistance.GEODESIC
CG_VIEW_DISTANCE_CHORDAL = ViewDistance.CHORDAL
CG_ATTENTION_MODEL_CROWD = AttentionModel.CROWD
CG_ATTENTION_MODEL_SALIENCY = AttentionModel.SALIENCY
CG_ATTENTION_MODEL_BASELINE = AttentionModel.BASELINE
CG_ATTENTION_MODEL_STREET = AttentionModel.STREET
CG_TARGET_PART_WHOLE = TargetPart.WHOLE
CG_TARGET_PART_HEAD = TargetPart.HEAD
CG_TARGET_PART_LEFT_EYE = TargetPart.LEFT_EYE
CG_TARGET_PART_RIGHT_EYE = TargetPart.RIGHT_EYE
CG_TARGET_PART_CHEST = TargetPart.CHEST
CG_TARGET_PART_TORSO = TargetPart.TORSO


# --- structs -------------------------------------------------------------------------------


class CheckedStructure(Structure):
    """Base of the header's structs: ctypes structs whose fields are checked on assignment.

    ``struct.field = value`` (and ``Struct(field=value)``) converts and checks ``value`` as
    every argument of the package is (``crowdgaze._checks``): an integer field takes an
    integer in its C type's range (else ``OverflowError``; ``2**32 + 3`` is never masked to
    3), a ``float`` field a real number a C float holds, a vector field a ``Vec3`` or three
    real numbers, and so on; a wrong type raises ``TypeError``. Both are
    ``crowdgaze.Error`` s. A name that is not a field raises ``AttributeError`` (a typo is
    not silently kept), as does any assignment to a read-only copy such as
    ``Crowd.config``, whose changes could not take effect.
    """

    #: Field name -> enum of its values, for ``repr`` (the C field is a plain uint32).
    _enums_: dict[str, type[enum.IntEnum]] = {}

    def __setattr__(self, name: str, value: Any) -> None:
        if name.startswith("_"):
            super().__setattr__(name, value)
            return
        kind = type(self).__name__
        if self.__dict__.get("_read_only_"):
            raise _field_error(
                f"{kind}.{name}: this {kind} is a read-only copy ({self._read_only_}); "
                f"changing it would change nothing",
                Status.WRONG_STATE,
            )
        field_type = _field_types(type(self)).get(name)
        if field_type is None:
            raise _field_error(f"{kind} has no field {name!r}", Status.INVALID_ARGUMENT)
        from ._arrays import field_value  # imported late: _arrays imports this module

        super().__setattr__(name, field_value(field_type, value, kind, name))

    def __repr__(self) -> str:
        fields = ", ".join(
            f"{name}={_show(getattr(self, name), self._enums_.get(name))}"
            for name in _field_types(type(self))
        )
        return f"{type(self).__name__}({fields})"

    def _freeze(self, why: str) -> None:
        """Makes this struct read-only; ``why`` says what it is a copy of."""
        self._read_only_ = why


_FIELD_TYPES: dict[type, dict[str, Any]] = {}


def _field_types(ctype: type) -> dict[str, Any]:
    """Field name -> ctypes type of the struct ``ctype``, in order."""
    types = _FIELD_TYPES.get(ctype)
    if types is None:
        types = _FIELD_TYPES[ctype] = {f[0]: f[1] for f in ctype._fields_}  # type: ignore[attr-defined]
    return types


def _field_error(message: str, status: Status) -> Exception:
    from ._exceptions import FieldError  # imported late: _exceptions imports this module

    return FieldError(status, message)


def _show(value: Any, values: type[enum.IntEnum] | None = None) -> str:
    """A field's value for ``repr``."""
    if isinstance(value, float):
        return format(value, ".7g")
    if isinstance(value, int) and values is not None:
        try:
            return f"{values.__name__}.{values(value).name}"
        except ValueError:
            return str(value)
    if isinstance(value, ctypes.Array):
        return "[" + ", ".join(_show(item) for item in value) + "]"
    if isinstance(value, ctypes._Pointer):
        return f"pointer({_show(value.contents)})" if value else "None"
    return repr(value)


class Vec3(CheckedStructure):
    """``cg_vec3``."""

    _fields_ = [("x", c_float), ("y", c_float), ("z", c_float)]

    def __iter__(self):
        return iter((self.x, self.y, self.z))

    def __repr__(self) -> str:
        return f"Vec3({self.x:g}, {self.y:g}, {self.z:g})"


class Quat(CheckedStructure):
    """``cg_quat``: x, y, z, w."""

    _fields_ = [("x", c_float), ("y", c_float), ("z", c_float), ("w", c_float)]

    def __iter__(self):
        return iter((self.x, self.y, self.z, self.w))

    def __repr__(self) -> str:
        return f"Quat({self.x:g}, {self.y:g}, {self.z:g}, {self.w:g})"


class ChainJoint(CheckedStructure):
    """``cg_chain_joint``."""

    _enums_ = {"role": JointRole}

    _fields_ = [
        ("role", c_uint32),
        ("offset", Vec3),
        ("rest", Quat),
        ("twist_axis", Vec3),
        ("max_swing", c_float),
        ("min_twist", c_float),
        ("max_twist", c_float),
    ]


class ChainDesc(CheckedStructure):
    """``cg_chain_desc``."""

    _fields_ = [
        ("struct_size", c_uint32),
        ("joint_count", c_uint32),
        ("joints", ChainJoint * CG_MAX_CHAIN_JOINTS),
        ("eye_forward", Vec3),
        ("eye_up", Vec3),
        ("root_offset", Vec3),
    ]


class CharacterDesc(CheckedStructure):
    """``cg_character_desc``."""

    _enums_ = {"attention_model": AttentionModel}

    _fields_ = [
        ("struct_size", c_uint32),
        ("heading", c_float),
        ("impact", c_float),
        ("position", Vec3),
        ("chain", POINTER(ChainDesc)),
        ("attention_model", c_uint32),
    ]


class ObjectDesc(CheckedStructure):
    """``cg_object_desc``."""

    _fields_ = [
        ("struct_size", c_uint32),
        ("heading", c_float),
        ("look_at_height", c_float),
        ("impact", c_float),
        ("position", Vec3),
    ]


class EntityState(CheckedStructure):
    """``cg_entity_state``."""

    _fields_ = [
        ("struct_size", c_uint32),
        ("id", c_uint32),
        ("flags", c_uint32),
        ("heading", c_float),
        ("position", Vec3),
        ("velocity", Vec3),
    ]


class GazeInfo(CheckedStructure):
    """``cg_gaze_info``."""

    _enums_ = {"target_part": TargetPart}

    _fields_ = [
        ("character", c_uint32),
        ("target", c_uint32),
        ("target_part", c_uint32),
        ("head_target", c_uint32),
        ("attending", c_uint32),
        ("interest_count", c_uint32),
        ("target_position", Vec3),
        ("s_max", c_float),
        ("threshold", c_float),
        ("attentive_fraction", c_float),
    ]


class ScoreBreakdown(CheckedStructure):
    """``cg_score_breakdown``."""

    _fields_ = [
        ("distance", c_float),
        ("view_angle", c_float),
        ("heading_angle", c_float),
        ("relative_speed", c_float),
        ("proximity", c_float),
        ("speed", c_float),
        ("orientation", c_float),
        ("periphery", c_float),
        ("total", c_float),
        ("pruned", c_uint32),
    ]


class CharacterParams(CheckedStructure):
    """``cg_character_params``."""

    _enums_ = {"attention_model": AttentionModel}

    _fields_ = [
        ("struct_size", c_uint32),
        ("weight_proximity", c_float),
        ("weight_speed", c_float),
        ("weight_orientation", c_float),
        ("weight_periphery", c_float),
        ("attention_fraction", c_float),
        ("attention_model", c_uint32),
    ]


class Constraint(CheckedStructure):
    """``cg_constraint``."""

    _fields_ = [
        ("entity", c_uint32),
        ("s_max", c_float),
        ("begin", c_double),
        ("end", c_double),
    ]


class DualQuat(CheckedStructure):
    """``cg_dualquat``: real (rotation) then dual (translation) part."""

    _fields_ = [("real", Quat), ("dual", Quat)]


class ViewBlenderConfig(CheckedStructure):
    """``cg_view_blender_config``."""

    _enums_ = {"distance": ViewDistance, "method": BlendMethod}

    _fields_ = [
        ("struct_size", c_uint32),
        ("joint_count", c_uint32),
        ("key_count", c_uint32),
        ("alpha", c_float),
        ("distance", c_uint32),
        ("method", c_uint32),
        ("precision", c_float),
        ("max_iterations", c_uint32),
    ]


class CrowdConfig(CheckedStructure):
    """``cg_crowd_config``."""

    _enums_ = {"up_axis": Axis, "forward_axis": Axis, "eye_motion": EyeMotion}

    _fields_ = [
        ("struct_size", c_uint32),
        ("max_characters", c_uint32),
        ("seed", c_uint64),
        ("max_objects", c_uint32),
        ("up_axis", c_uint32),
        ("forward_axis", c_uint32),
        ("units_per_metre", c_float),
        ("max_recorded_states", c_uint32),
        ("max_distance", c_float),
        ("field_of_view", c_float),
        ("speed_weight", c_float),
        ("periphery_max_angle", c_float),
        ("min_interest_time", c_float),
        ("max_interest_time", c_float),
        ("interest_cooldown", c_float),
        ("threshold_warmup", c_float),
        ("initial_threshold", c_float),
        ("attention_fraction_min", c_float),
        ("attention_fraction_max", c_float),
        ("eyes_only_angle", c_float),
        ("eyes_head_neck_angle", c_float),
        ("head_speed", c_float),
        ("max_activation_time", c_float),
        ("restart_distance", c_float),
        ("min_deactivation_time", c_float),
        ("max_deactivation_time", c_float),
        ("eye_fixation_time", c_float),
        ("head_fixation_time", c_float),
        ("random_pick_probability", c_float),
        ("social_weight", c_float),
        ("proximity_radius", c_float),
        ("attention_period", c_uint32),
        ("lod_distance", c_float),
        ("far_attention_period", c_uint32),
        ("threads", c_uint32),
        ("reorder_period", c_uint32),
        ("blink_rate", c_float),
        ("blink_rate_spread", c_float),
        ("evoked_blink_min_amplitude", c_float),
        ("evoked_blink_full_amplitude", c_float),
        ("evoked_blink_probability", c_float),
        ("lid_gain", c_float),
        ("eye_motion", c_uint32),
        ("max_conversations", c_uint32),
        ("talking_gain", c_float),
        ("eye_part_weight", c_float),
        ("listener_look_share", c_float),
        ("listener_glance_time", c_float),
        ("speaker_look_share", c_float),
        ("speaker_glance_time", c_float),
        ("idle_look_share", c_float),
        ("idle_glance_time", c_float),
        ("turn_start_aversion_time", c_float),
        ("street_view_half_angle", c_float),
        ("street_first_fixation_probability", c_float),
        ("street_latency_min", c_float),
        ("street_latency_max", c_float),
        ("street_fixation_median", c_float),
        ("street_fixation_log_spread", c_float),
        ("street_refixation_probability", c_float),
        ("street_refixation_gap_min", c_float),
        ("street_refixation_gap_max", c_float),
        ("street_civil_distance", c_float),
        ("street_civil_look_probability", c_float),
        ("street_path_look_distance", c_float),
        ("street_civil_look_distance", c_float),
        ("follow_enabled", c_uint32),
        ("follow_one_looker_probability", c_float),
        ("follow_max_probability", c_float),
        ("follow_distance", c_float),
        ("follow_view_half_angle", c_float),
        ("follow_oncoming_weight", c_float),
        ("follow_glance_cue_weight", c_float),
        ("follow_glance_min", c_float),
        ("follow_glance_max", c_float),
        ("follow_forget_time", c_float),
        ("street_miss_after", c_float),
        ("follow_reaction_min", c_float),
        ("follow_reaction_max", c_float),
    ]


class GazeTarget(CheckedStructure):
    """``cg_gaze_target``."""

    _fields_ = [
        ("struct_size", c_uint32),
        ("kind", c_uint32),
        ("priority", c_uint32),
        ("entity", c_uint32),
        ("point", Vec3),
    ]


class EyeInfo(CheckedStructure):
    """``cg_eye_info``."""

    _fields_ = [
        ("character", c_uint32),
        ("left_origin", Vec3),
        ("right_origin", Vec3),
        ("left_direction", Vec3),
        ("right_direction", Vec3),
    ]


class Eyelids(CheckedStructure):
    """``cg_eyelids``: a character's blink closures (0 open, 1 closed) and upper lid
    pitches (radians)."""

    _fields_ = [
        ("character", c_uint32),
        ("left_closure", c_float),
        ("right_closure", c_float),
        ("left_lid_pitch", c_float),
        ("right_lid_pitch", c_float),
    ]


class RigDesc(CheckedStructure):
    """``cg_rig_desc``: a skeleton at rest and how to map it (see ``crowdgaze.Rig``, which
    fills one from Python values; the pointers must stay valid for ``cg_rig_create``)."""

    _enums_ = {"up": Axis, "forward": Axis, "crowd_up": Axis, "crowd_forward": Axis}

    _fields_ = [
        ("struct_size", c_uint32),
        ("bone_count", c_uint32),
        ("bone_names", POINTER(c_char_p)),
        ("parents", POINTER(c_int32)),
        ("rest_translations", POINTER(Vec3)),
        ("rest_rotations", POINTER(Quat)),
        ("units_per_metre", c_float),
        ("up", c_uint32),
        ("forward", c_uint32),
        ("bone_map", c_char_p),
        ("crowd_up", c_uint32),
        ("crowd_forward", c_uint32),
        ("crowd_units_per_metre", c_float),
    ]


class CrowdHandle(Structure):
    """``cg_crowd`` (opaque): only ever used through a pointer."""


class ViewBlenderHandle(Structure):
    """``cg_view_blender`` (opaque): only ever used through a pointer."""


class RigHandle(Structure):
    """``cg_rig`` (opaque): only ever used through a pointer."""


#: C struct name -> ctypes type (the opaque handles included).
STRUCTS = {
    "cg_vec3": Vec3,
    "cg_quat": Quat,
    "cg_chain_joint": ChainJoint,
    "cg_chain_desc": ChainDesc,
    "cg_character_desc": CharacterDesc,
    "cg_object_desc": ObjectDesc,
    "cg_entity_state": EntityState,
    "cg_gaze_info": GazeInfo,
    "cg_score_breakdown": ScoreBreakdown,
    "cg_character_params": CharacterParams,
    "cg_constraint": Constraint,
    "cg_dualquat": DualQuat,
    "cg_view_blender_config": ViewBlenderConfig,
    "cg_crowd_config": CrowdConfig,
    "cg_gaze_target": GazeTarget,
    "cg_eye_info": EyeInfo,
    "cg_eyelids": Eyelids,
    "cg_rig_desc": RigDesc,
    "cg_crowd": CrowdHandle,
    "cg_view_blender": ViewBlenderHandle,
    "cg_rig": RigHandle,
}


# --- functions -----------------------------------------------------------------------------

_status = c_uint32  # cg_status is a uint32_t in C
_P = POINTER

#: Every function of the header: name -> (restype, argtypes).
FUNCTIONS = {
    "cg_character_desc_init": (_status, [_P(CharacterDesc)]),
    "cg_object_desc_init": (_status, [_P(ObjectDesc)]),
    "cg_entity_state_init": (_status, [_P(EntityState)]),
    "cg_crowd_add_character": (_status, [_P(CrowdHandle), _P(CharacterDesc), _P(c_uint32)]),
    "cg_crowd_add_object": (_status, [_P(CrowdHandle), _P(ObjectDesc), _P(c_uint32)]),
    "cg_crowd_remove_entity": (_status, [_P(CrowdHandle), c_uint32]),
    "cg_crowd_character_count": (_status, [_P(CrowdHandle), _P(c_size_t)]),
    "cg_crowd_push_frame": (_status, [_P(CrowdHandle), c_double, _P(EntityState), c_size_t]),
    "cg_crowd_begin_push": (_status, [_P(CrowdHandle), c_double]),
    "cg_crowd_push_range": (_status, [_P(CrowdHandle), _P(EntityState), c_size_t]),
    "cg_crowd_end_push": (_status, [_P(CrowdHandle)]),
    "cg_crowd_step": (_status, [_P(CrowdHandle), c_float]),
    "cg_crowd_begin_step": (_status, [_P(CrowdHandle), c_float]),
    "cg_crowd_step_range": (_status, [_P(CrowdHandle), c_uint32, c_uint32]),
    "cg_crowd_end_step": (_status, [_P(CrowdHandle)]),
    "cg_crowd_read_gaze": (_status, [_P(CrowdHandle), _P(GazeInfo), c_size_t, _P(c_size_t)]),
    "cg_crowd_score": (_status, [_P(CrowdHandle), c_uint32, c_uint32, _P(ScoreBreakdown)]),
    "cg_crowd_get_character_params": (
        _status,
        [_P(CrowdHandle), c_uint32, _P(CharacterParams)],
    ),
    "cg_crowd_set_character_params": (
        _status,
        [_P(CrowdHandle), c_uint32, _P(CharacterParams)],
    ),
    "cg_crowd_set_impact": (_status, [_P(CrowdHandle), c_uint32, c_float]),
    "cg_crowd_plan": (_status, [_P(CrowdHandle)]),
    "cg_crowd_clear_plan": (_status, [_P(CrowdHandle)]),
    "cg_crowd_read_constraints": (
        _status,
        [_P(CrowdHandle), c_uint32, _P(Constraint), c_size_t, _P(c_size_t)],
    ),
    "cg_crowd_set_viewer": (_status, [_P(CrowdHandle), _P(Vec3), c_float, _P(c_uint32)]),
    "cg_crowd_set_attention_period": (_status, [_P(CrowdHandle), c_uint32, c_uint32]),
    "cg_dualquat_from_rt": (_status, [_P(Quat), _P(Vec3), _P(DualQuat)]),
    "cg_dualquat_to_rt": (_status, [_P(DualQuat), _P(Quat), _P(Vec3)]),
    "cg_dualquat_from_matrix": (_status, [_P(c_float), _P(DualQuat)]),
    "cg_dualquat_to_matrix": (_status, [_P(DualQuat), _P(c_float)]),
    "cg_blend_dlb": (_status, [_P(DualQuat), _P(c_float), c_size_t, _P(DualQuat)]),
    "cg_blend_dib": (
        _status,
        [_P(DualQuat), _P(c_float), c_size_t, c_float, c_uint32, _P(DualQuat)],
    ),
    "cg_blend_pose_dlb": (
        _status,
        [_P(DualQuat), _P(c_float), c_size_t, c_size_t, _P(DualQuat)],
    ),
    "cg_blend_pose_dib": (
        _status,
        [_P(DualQuat), _P(c_float), c_size_t, c_size_t, c_float, c_uint32, _P(DualQuat)],
    ),
    "cg_camera_center_from_projection": (_status, [_P(c_float), _P(Vec3)]),
    "cg_view_blender_config_init": (_status, [_P(ViewBlenderConfig)]),
    "cg_view_blender_create": (_status, [_P(ViewBlenderConfig), _P(_P(ViewBlenderHandle))]),
    "cg_view_blender_destroy": (None, [_P(ViewBlenderHandle)]),
    "cg_view_blender_set_key_clip": (
        _status,
        [_P(ViewBlenderHandle), c_uint32, _P(DualQuat), c_size_t, c_float, c_bool],
    ),
    "cg_view_blender_set_key_pose": (
        _status,
        [_P(ViewBlenderHandle), c_uint32, _P(DualQuat), c_size_t],
    ),
    "cg_view_blender_add_camera": (_status, [_P(ViewBlenderHandle), Vec3, c_uint32]),
    "cg_view_blender_weights": (
        _status,
        [_P(ViewBlenderHandle), _P(DualQuat), _P(Vec3), _P(c_float), c_size_t],
    ),
    "cg_view_blender_evaluate": (
        _status,
        [_P(ViewBlenderHandle), _P(DualQuat), _P(Vec3), c_double, _P(DualQuat), c_size_t],
    ),
    "cg_chain_desc_init_human": (_status, [_P(ChainDesc), c_uint32, c_uint32]),
    "cg_crowd_config_init": (_status, [_P(CrowdConfig)]),
    "cg_crowd_config_init_street": (_status, [_P(CrowdConfig)]),
    "cg_crowd_create": (_status, [_P(CrowdConfig), _P(_P(CrowdHandle))]),
    "cg_crowd_destroy": (None, [_P(CrowdHandle)]),
    "cg_crowd_get_config": (_status, [_P(CrowdHandle), _P(CrowdConfig)]),
    "cg_crowd_read_eyelids": (
        _status,
        [_P(CrowdHandle), c_uint32, c_uint32, _P(Eyelids), c_size_t],
    ),
    "cg_gaze_target_init": (_status, [_P(GazeTarget)]),
    "cg_crowd_set_gaze_target": (_status, [_P(CrowdHandle), c_uint32, _P(GazeTarget)]),
    "cg_crowd_clear_gaze_target": (_status, [_P(CrowdHandle), c_uint32]),
    "cg_crowd_set_conversation": (
        _status,
        [_P(CrowdHandle), _P(c_uint32), c_size_t, _P(c_uint32)],
    ),
    "cg_crowd_remove_conversation": (_status, [_P(CrowdHandle), c_uint32]),
    "cg_crowd_get_conversation": (_status, [_P(CrowdHandle), c_uint32, _P(c_uint32)]),
    "cg_crowd_read_following": (
        _status,
        [_P(CrowdHandle), c_uint32, _P(Vec3), _P(c_uint32), _P(c_uint32)],
    ),
    "cg_crowd_set_base_pose": (_status, [_P(CrowdHandle), c_uint32, _P(Quat), c_size_t]),
    "cg_crowd_set_base_poses": (
        _status,
        [_P(CrowdHandle), _P(c_uint32), c_size_t, _P(Quat), c_size_t],
    ),
    "cg_crowd_joint_total": (_status, [_P(CrowdHandle), c_uint32, c_uint32, _P(c_size_t)]),
    "cg_crowd_read_joints": (
        _status,
        [_P(CrowdHandle), c_uint32, c_uint32, _P(Quat), c_size_t],
    ),
    "cg_crowd_read_joint_deltas": (
        _status,
        [_P(CrowdHandle), c_uint32, c_uint32, _P(Quat), c_size_t],
    ),
    "cg_crowd_read_eyes": (
        _status,
        [_P(CrowdHandle), c_uint32, c_uint32, _P(EyeInfo), c_size_t],
    ),
    "cg_rig_desc_init": (_status, [_P(RigDesc)]),
    "cg_rig_create": (_status, [_P(RigDesc), _P(_P(RigHandle))]),
    "cg_rig_destroy": (None, [_P(RigHandle)]),
    "cg_rig_chain": (_status, [_P(RigHandle), _P(ChainDesc)]),
    "cg_rig_bone_count": (_status, [_P(RigHandle), _P(c_uint32)]),
    "cg_rig_joint_count": (_status, [_P(RigHandle), _P(c_uint32)]),
    "cg_rig_chain_bones": (_status, [_P(RigHandle), _P(c_uint32), c_size_t]),
    "cg_rig_bone_roles": (_status, [_P(RigHandle), _P(c_uint32), c_size_t]),
    "cg_rig_report": (c_size_t, [_P(RigHandle), c_char_p, c_size_t]),
    "cg_rig_base_pose": (_status, [_P(RigHandle), _P(Quat), c_size_t, _P(Quat), c_size_t]),
    "cg_rig_write_joints": (
        _status,
        [_P(RigHandle), _P(Quat), c_size_t, _P(Quat), c_size_t],
    ),
    "cg_last_error_message": (c_size_t, [c_char_p, c_size_t]),
    "cg_status_str": (c_char_p, [c_uint32]),
    "cg_version": (c_uint32, []),
    "cg_version_string": (c_char_p, []),
}


# --- the shared library --------------------------------------------------------------------


def _library_file_name() -> str:
    if sys.platform == "darwin":
        return "libcrowdgaze.dylib"
    if sys.platform == "win32":
        return "crowdgaze.dll"
    return "libcrowdgaze.so"


def _cargo_target_dir() -> Path:
    """The Cargo target directory of the repository this package sits in."""
    configured = os.environ.get("CARGO_TARGET_DIR")
    if configured:
        return Path(configured)
    repository = Path(__file__).resolve().parents[3]
    return repository / "target"


def _bundled_library() -> Path | None:
    """The library inside the installed wheel: the extension module ``crowdgaze._crowdgaze``
    that maturin builds from ``bindings/python/Cargo.toml``, which exports every ``cg_``
    function of the header. None in a source tree, where no wheel was built."""
    here = Path(__file__).resolve().parent
    for path in sorted(here.glob("_crowdgaze*.so")) + sorted(here.glob("_crowdgaze*.pyd")):
        if path.is_file():
            return path
    return None


def library_candidates() -> list[Path]:
    """Where ``find_library`` looks after the bundled library, in order (the env var
    aside): the newest of the Cargo builds of the repository holding this package."""
    target = _cargo_target_dir()
    cargo_builds = [target / profile / _library_file_name() for profile in ("release", "debug")]
    # Of the Cargo builds, the most recently built first.
    existing = sorted(
        (p for p in cargo_builds if p.is_file()), key=lambda p: p.stat().st_mtime, reverse=True
    )
    return existing + [p for p in cargo_builds if p not in existing]


def find_library() -> Path:
    """The shared library to load: ``$CROWDGAZE_LIBRARY`` if set; else the library the
    installed wheel bundles (``crowdgaze/_crowdgaze*.so``); else, in a source tree, the
    newest of the Cargo builds ``target/release`` and ``target/debug`` (``$CARGO_TARGET_DIR``
    if set) of the repository holding the package.
    """
    configured = os.environ.get("CROWDGAZE_LIBRARY")
    if configured:
        path = Path(configured)
        if not path.is_file():
            raise OSError(f"CROWDGAZE_LIBRARY={configured} is not a file")
        # Absolute, so that `library_path` still names it after a change of directory.
        return path.resolve()
    bundled = _bundled_library()
    if bundled is not None:
        return bundled
    for path in library_candidates():
        if path.is_file():
            return path
    looked = ", ".join(str(p) for p in library_candidates())
    raise OSError(
        "crowdgaze: shared library not found; install the package with "
        "`pip install ./bindings/python`, or in the source tree build it with "
        f"`cargo build --release` or set CROWDGAZE_LIBRARY (looked at: {looked})"
    )


def load(path: Path | str | None = None) -> ctypes.CDLL:
    """Loads the library and declares every function's ``restype`` and ``argtypes``."""
    path = Path(path) if path is not None else find_library()
    library = ctypes.CDLL(str(path))
    for name, (restype, argtypes) in FUNCTIONS.items():
        function = getattr(library, name)
        function.restype = restype
        function.argtypes = argtypes
    version = library.cg_version()
    major, minor = version >> 16, (version >> 8) & 0xFF
    if major != CG_VERSION_MAJOR or (major == 0 and minor != CG_VERSION_MINOR):
        raise ImportError(
            f"crowdgaze: the library at {path} is version "
            f"{library.cg_version_string().decode()}, these bindings are "
            f"{CG_VERSION_MAJOR}.{CG_VERSION_MINOR}.{CG_VERSION_PATCH}"
        )
    return library
