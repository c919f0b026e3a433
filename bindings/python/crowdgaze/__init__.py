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

# Every CG_ constant and enum value under its C name (CG_NO_TARGET, CG_AXIS_POSITIVE_Y, ...).
for _name in dir(_native):
    if _name.startswith("CG_"):
        globals()[_name] = getattr(_native, _name)
del _name

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
