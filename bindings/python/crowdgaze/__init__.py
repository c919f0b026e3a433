"""crowdgaze for Python: believable gaze for every character of a crowd.

A ctypes binding of the crowdgaze C library (``include/crowdgaze.h``). The installed wheel
carries the library (``crowdgaze/_crowdgaze*.so``); ``$CROWDGAZE_LIBRARY`` overrides it, and
in a source tree the newest Cargo build (``target/release`` or ``target/debug``) is used.

>>> import crowdgaze as cg
>>> crowd = cg.Crowd(max_characters=10, seed=1)
>>> me = crowd.add_character((0, 0, 0))
>>> crowd.set_gaze_target(me, point=(1.0, 1.6, 2.0))
>>> crowd.step(1 / 30)
>>> crowd.read_joints().shape
(10, 4)

Every function of the header is declared on ``crowdgaze.lib`` with its ``argtypes`` and
``restype``; the structs are ctypes ``Structure`` s with the header's fields and order
(``STRUCTS`` maps C names to them); every ``CG_`` constant and enum value is here under its
C name. Failures raise ``crowdgaze.Error`` (``status``, ``message``, ``function``).

Arguments are checked before any C call: a wrong type raises ``TypeError``, an integer out
of its C type's range ``OverflowError``, a wrong shape or layout ``ValueError``, each naming
the argument; ``out=`` arrays must be writeable, C-contiguous and of the exact dtype and
shape. A ``Crowd`` or ``ViewBlender`` cannot be copied or pickled, and ``close()`` from
another thread waits for the calls in flight (``crowdgaze._checks``, ``crowdgaze._owner``).
"""

from __future__ import annotations

from . import _native
from ._arrays import (
    CONSTRAINT_DTYPE,
    ENTITY_STATE_DTYPE,
    EYE_INFO_DTYPE,
    EYELIDS_DTYPE,
    GAZE_INFO_DTYPE,
    RECORD_DTYPES,
)
from ._errors import last_error_message, status_string
from ._exceptions import (
    ArgumentRangeError,
    ArgumentTypeError,
    CapacityError,
    ClosedError,
    Error,
    FieldError,
    InternalError,
    InvalidArgumentError,
    NonFiniteError,
    NotConvergedError,
    NotFoundError,
    OutOfMemoryError,
    WrongStateError,
)
from ._library import lib, library_path
from ._native import (
    CG_ATTENTION_MODEL_BASELINE,
    CG_ATTENTION_MODEL_CROWD,
    CG_ATTENTION_MODEL_SALIENCY,
    CG_AXIS_NEGATIVE_X,
    CG_AXIS_NEGATIVE_Y,
    CG_AXIS_NEGATIVE_Z,
    CG_AXIS_POSITIVE_X,
    CG_AXIS_POSITIVE_Y,
    CG_AXIS_POSITIVE_Z,
    CG_BLEND_METHOD_DIB,
    CG_BLEND_METHOD_DLB,
    CG_EYE_MOTION_MAIN_SEQUENCE,
    CG_EYE_MOTION_PAPER,
    CG_GAZE_PRIORITY_OVERRIDE,
    CG_GAZE_PRIORITY_WHEN_IDLE,
    CG_GAZE_TARGET_ENTITY,
    CG_GAZE_TARGET_POINT,
    CG_JOINT_ROLE_CERVICAL,
    CG_JOINT_ROLE_HEAD,
    CG_JOINT_ROLE_LEFT_EYE,
    CG_JOINT_ROLE_RIGHT_EYE,
    CG_JOINT_ROLE_SPINE,
    CG_MAX_CHAIN_JOINTS,
    CG_MAX_CONVERSATION_MEMBERS,
    CG_NO_TARGET,
    CG_STATE_HAS_VELOCITY,
    CG_STATE_HEADING_FROM_MOTION,
    CG_STATE_TALKING,
    CG_STATUS_BAD_STRUCT_SIZE,
    CG_STATUS_CAPACITY,
    CG_STATUS_INTERNAL,
    CG_STATUS_INVALID_ARGUMENT,
    CG_STATUS_NON_FINITE,
    CG_STATUS_NOT_CONVERGED,
    CG_STATUS_NOT_FOUND,
    CG_STATUS_NULL_ARGUMENT,
    CG_STATUS_OK,
    CG_STATUS_OUT_OF_MEMORY,
    CG_STATUS_POISONED,
    CG_STATUS_WRONG_STATE,
    CG_TARGET_PART_CHEST,
    CG_TARGET_PART_HEAD,
    CG_TARGET_PART_LEFT_EYE,
    CG_TARGET_PART_RIGHT_EYE,
    CG_TARGET_PART_TORSO,
    CG_TARGET_PART_WHOLE,
    CG_VERSION_MAJOR,
    CG_VERSION_MINOR,
    CG_VERSION_PATCH,
    CG_VIEW_DISTANCE_CHORDAL,
    CG_VIEW_DISTANCE_GEODESIC,
    ENUMS,
    FUNCTIONS,
    STRUCTS,
    AttentionModel,
    Axis,
    BlendMethod,
    ChainDesc,
    ChainJoint,
    CharacterDesc,
    CharacterParams,
    Constraint,
    CrowdConfig,
    DualQuat,
    EntityState,
    EyeInfo,
    Eyelids,
    EyeMotion,
    GazeInfo,
    GazeTarget,
    JointRole,
    ObjectDesc,
    Quat,
    ScoreBreakdown,
    StateFlag,
    Status,
    TargetPart,
    Vec3,
    ViewBlenderConfig,
    ViewDistance,
    find_library,
)
from .blend import (
    NotConvergedWarning,
    ViewBlender,
    blend_dib,
    blend_dlb,
    blend_pose_dib,
    blend_pose_dlb,
    camera_center_from_projection,
    dualquat_from_matrix,
    dualquat_from_rt,
    dualquat_to_matrix,
    dualquat_to_rt,
    view_blender_config,
)
from .crowd import (
    Crowd,
    chain_desc_human,
    character_desc,
    crowd_config,
    entity_states,
    gaze_target,
    object_desc,
)


cg_quat_IDENTITY = _native.cg_quat_IDENTITY
NO_TARGET = _native.CG_NO_TARGET
STATE_HEADING_FROM_MOTION = _native.CG_STATE_HEADING_FROM_MOTION
STATE_HAS_VELOCITY = _native.CG_STATE_HAS_VELOCITY
STATE_TALKING = _native.CG_STATE_TALKING
GAZE_PRIORITY_OVERRIDE = _native.CG_GAZE_PRIORITY_OVERRIDE
GAZE_PRIORITY_WHEN_IDLE = _native.CG_GAZE_PRIORITY_WHEN_IDLE

__version__ = f"{_native.CG_VERSION_MAJOR}.{_native.CG_VERSION_MINOR}.{_native.CG_VERSION_PATCH}"


def version() -> int:
    """The loaded library's version, ``(major << 16) | (minor << 8) | patch``."""
    return lib.cg_version()


def version_string() -> str:
    """The loaded library's version, "major.minor.patch"."""
    return lib.cg_version_string().decode()

#: The public API (every CG_ constant of the header included).
__all__ = [
    "__version__",
    "ArgumentRangeError",
    "ArgumentTypeError",
    "AttentionModel",
    "Axis",
    "blend_dib",
    "blend_dlb",
    "blend_pose_dib",
    "blend_pose_dlb",
    "BlendMethod",
    "camera_center_from_projection",
    "CapacityError",
    "cg_quat_IDENTITY",
    "chain_desc_human",
    "ChainDesc",
    "ChainJoint",
    "character_desc",
    "CharacterDesc",
    "CharacterParams",
    "ClosedError",
    "Constraint",
    "CONSTRAINT_DTYPE",
    "Crowd",
    "crowd_config",
    "CrowdConfig",
    "DualQuat",
    "dualquat_from_matrix",
    "dualquat_from_rt",
    "dualquat_to_matrix",
    "dualquat_to_rt",
    "ENTITY_STATE_DTYPE",
    "entity_states",
    "EntityState",
    "ENUMS",
    "Error",
    "EYE_INFO_DTYPE",
    "EyeInfo",
    "Eyelids",
    "EYELIDS_DTYPE",
    "EyeMotion",
    "FieldError",
    "find_library",
    "FUNCTIONS",
    "GAZE_INFO_DTYPE",
    "GAZE_PRIORITY_OVERRIDE",
    "GAZE_PRIORITY_WHEN_IDLE",
    "gaze_target",
    "GazeInfo",
    "GazeTarget",
    "InternalError",
    "InvalidArgumentError",
    "JointRole",
    "last_error_message",
    "lib",
    "library_path",
    "NO_TARGET",
    "NonFiniteError",
    "NotConvergedError",
    "NotConvergedWarning",
    "NotFoundError",
    "object_desc",
    "ObjectDesc",
    "OutOfMemoryError",
    "Quat",
    "RECORD_DTYPES",
    "ScoreBreakdown",
    "STATE_HAS_VELOCITY",
    "STATE_HEADING_FROM_MOTION",
    "STATE_TALKING",
    "StateFlag",
    "Status",
    "status_string",
    "STRUCTS",
    "TargetPart",
    "Vec3",
    "version",
    "version_string",
    "view_blender_config",
    "ViewBlender",
    "ViewBlenderConfig",
    "ViewDistance",
    "WrongStateError",
    "CG_ATTENTION_MODEL_BASELINE",
    "CG_ATTENTION_MODEL_CROWD",
    "CG_ATTENTION_MODEL_SALIENCY",
    "CG_AXIS_NEGATIVE_X",
    "CG_AXIS_NEGATIVE_Y",
    "CG_AXIS_NEGATIVE_Z",
    "CG_AXIS_POSITIVE_X",
    "CG_AXIS_POSITIVE_Y",
    "CG_AXIS_POSITIVE_Z",
    "CG_BLEND_METHOD_DIB",
    "CG_BLEND_METHOD_DLB",
    "CG_EYE_MOTION_MAIN_SEQUENCE",
    "CG_EYE_MOTION_PAPER",
    "CG_GAZE_PRIORITY_OVERRIDE",
    "CG_GAZE_PRIORITY_WHEN_IDLE",
    "CG_GAZE_TARGET_ENTITY",
    "CG_GAZE_TARGET_POINT",
    "CG_JOINT_ROLE_CERVICAL",
    "CG_JOINT_ROLE_HEAD",
    "CG_JOINT_ROLE_LEFT_EYE",
    "CG_JOINT_ROLE_RIGHT_EYE",
    "CG_JOINT_ROLE_SPINE",
    "CG_MAX_CHAIN_JOINTS",
    "CG_MAX_CONVERSATION_MEMBERS",
    "CG_NO_TARGET",
    "CG_STATE_HAS_VELOCITY",
    "CG_STATE_HEADING_FROM_MOTION",
    "CG_STATE_TALKING",
    "CG_STATUS_BAD_STRUCT_SIZE",
    "CG_STATUS_CAPACITY",
    "CG_STATUS_INTERNAL",
    "CG_STATUS_INVALID_ARGUMENT",
    "CG_STATUS_NON_FINITE",
    "CG_STATUS_NOT_CONVERGED",
    "CG_STATUS_NOT_FOUND",
    "CG_STATUS_NULL_ARGUMENT",
    "CG_STATUS_OK",
    "CG_STATUS_OUT_OF_MEMORY",
    "CG_STATUS_POISONED",
    "CG_STATUS_WRONG_STATE",
    "CG_TARGET_PART_CHEST",
    "CG_TARGET_PART_HEAD",
    "CG_TARGET_PART_LEFT_EYE",
    "CG_TARGET_PART_RIGHT_EYE",
    "CG_TARGET_PART_TORSO",
    "CG_TARGET_PART_WHOLE",
    "CG_VERSION_MAJOR",
    "CG_VERSION_MINOR",
    "CG_VERSION_PATCH",
    "CG_VIEW_DISTANCE_CHORDAL",
    "CG_VIEW_DISTANCE_GEODESIC",
]
