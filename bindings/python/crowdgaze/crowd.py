"""``crowdgaze.Crowd``: attention and gaze IK for a crowd (the ``cg_crowd`` handle)."""

from __future__ import annotations

import ctypes
from ctypes import POINTER, byref, c_size_t, c_uint32

import numpy as np

from . import _arrays as a
from . import _native as n
from ._errors import check
from ._library import lib


def _fill(struct, fields: dict, what: str):
    known = {name for name, *_ in struct._fields_}
    for name, value in fields.items():
        if name not in known:
            raise TypeError(f"{what} has no field {name!r}")
        if isinstance(getattr(struct, name), n.Vec3):
            value = a.vec3(value, name)
        setattr(struct, name, value)
    return struct


def crowd_config(**fields) -> n.CrowdConfig:
    """A ``CrowdConfig`` with the library's defaults (``cg_crowd_config_init``), then
    ``fields`` set (``crowd_config(max_characters=100, seed=7)``)."""
    config = n.CrowdConfig()
    check(lib.cg_crowd_config_init(byref(config)), "cg_crowd_config_init")
    return _fill(config, fields, "cg_crowd_config")


def character_desc(**fields) -> n.CharacterDesc:
    """A ``CharacterDesc`` with defaults, then ``fields`` (``position`` a 3-sequence)."""
    desc = n.CharacterDesc()
    check(lib.cg_character_desc_init(byref(desc)), "cg_character_desc_init")
    return _fill(desc, fields, "cg_character_desc")


def object_desc(**fields) -> n.ObjectDesc:
    """An ``ObjectDesc`` with defaults, then ``fields``."""
    desc = n.ObjectDesc()
    check(lib.cg_object_desc_init(byref(desc)), "cg_object_desc_init")
    return _fill(desc, fields, "cg_object_desc")


def gaze_target(**fields) -> n.GazeTarget:
    """A ``GazeTarget`` with defaults (a point target, overriding), then ``fields``."""
    target = n.GazeTarget()
    check(lib.cg_gaze_target_init(byref(target)), "cg_gaze_target_init")
    return _fill(target, fields, "cg_gaze_target")


def chain_desc_human(up_axis=n.Axis.POSITIVE_Y, forward_axis=n.Axis.POSITIVE_Z) -> n.ChainDesc:
    """The human gaze chain (5 spine, 2 cervical, head, 2 eyes; metres) for these axes."""
    desc = n.ChainDesc()
    check(
        lib.cg_chain_desc_init_human(byref(desc), int(up_axis), int(forward_axis)),
        "cg_chain_desc_init_human",
    )
    return desc


def entity_states(ids, positions=None, flags=n.CG_STATE_HEADING_FROM_MOTION) -> np.ndarray:
    """A numpy record array of ``cg_entity_state`` (``ENTITY_STATE_DTYPE``) for ``ids``, each
    initialised by ``cg_entity_state_init``, with ``flags`` and, if given, ``positions``
    (``(n, 3)``). Set ``states["position"]`` (an ``(n, 3)`` float32 view) each frame and pass
    the array to ``Crowd.push_frame``: it goes to C without a copy."""
    ids = np.asarray(ids, dtype=np.uint32).reshape(-1)
    template = n.EntityState()
    check(lib.cg_entity_state_init(byref(template)), "cg_entity_state_init")
    states = np.zeros(ids.size, dtype=a.ENTITY_STATE_DTYPE)
    states["struct_size"] = template.struct_size
    states["heading"] = template.heading
    states["id"] = ids
    states["flags"] = flags
    if positions is not None:
        states["position"] = np.asarray(positions, dtype=np.float32).reshape(ids.size, 3)
    return states


class Crowd:
    """A crowd of characters and the objects they may look at.

    ``Crowd(config)`` or ``Crowd(max_characters=..., seed=...)`` (fields of
    ``crowd_config``). Release it with ``close()`` or a ``with`` block (or let it be
    collected). Every method raises ``crowdgaze.Error`` on failure; a failed call changes
    nothing. Not safe for concurrent mutation.
    """

    def __init__(self, config: n.CrowdConfig | None = None, **fields):
        if config is None:
            config = crowd_config(**fields)
        elif fields:
            config = _fill(n.CrowdConfig.from_buffer_copy(config), fields, "cg_crowd_config")
        handle = POINTER(n.CrowdHandle)()
        check(lib.cg_crowd_create(byref(config), byref(handle)), "cg_crowd_create")
        self._handle = handle

    # --- lifetime ---------------------------------------------------------------------------

    @property
    def handle(self):
        """The ``cg_crowd*`` (a ctypes pointer), for calling ``crowdgaze.lib`` directly."""
        if not self._handle:
            raise ValueError("crowd is closed")
        return self._handle

    def close(self) -> None:
        """Destroys the crowd (``cg_crowd_destroy``); later calls raise ``ValueError``."""
        handle, self._handle = getattr(self, "_handle", None), POINTER(n.CrowdHandle)()
        if handle:
            lib.cg_crowd_destroy(handle)

    def __enter__(self) -> Crowd:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        self.close()

    # --- setup ------------------------------------------------------------------------------

    @property
    def config(self) -> n.CrowdConfig:
        """The settings the crowd was created with."""
        config = n.CrowdConfig()
        check(lib.cg_crowd_get_config(self.handle, byref(config)), "cg_crowd_get_config")
        return config

    def add_character(
        self, position=(0.0, 0.0, 0.0), heading: float = 0.0, *, desc=None, chain=None, **fields
    ) -> int:
        """Adds a character; returns its id. Either a ready ``desc`` (``CharacterDesc``) or
        ``position``, ``heading``, ``chain`` (a ``ChainDesc``, default the human chain) and
        other ``CharacterDesc`` fields."""
        if desc is None:
            desc = character_desc(position=position, heading=heading, **fields)
            if chain is not None:
                desc.chain = ctypes.pointer(chain)
        out = c_uint32()
        check(
            lib.cg_crowd_add_character(self.handle, byref(desc), byref(out)),
            "cg_crowd_add_character",
        )
        return out.value

    def add_object(self, position=(0.0, 0.0, 0.0), *, desc=None, **fields) -> int:
        """Adds a scene object; returns its id (``fields``: heading, look_at_height, impact)."""
        if desc is None:
            desc = object_desc(position=position, **fields)
        out = c_uint32()
        check(lib.cg_crowd_add_object(self.handle, byref(desc), byref(out)), "cg_crowd_add_object")
        return out.value

    def remove_entity(self, entity: int) -> None:
        check(lib.cg_crowd_remove_entity(self.handle, entity), "cg_crowd_remove_entity")

    def character_count(self) -> int:
        out = c_size_t()
        check(lib.cg_crowd_character_count(self.handle, byref(out)), "cg_crowd_character_count")
        return out.value

    def __len__(self) -> int:
        return self.character_count()

    def character_params(self, character: int) -> n.CharacterParams:
        out = n.CharacterParams()
        check(
            lib.cg_crowd_get_character_params(self.handle, character, byref(out)),
            "cg_crowd_get_character_params",
        )
        return out

    def set_character_params(self, character: int, params=None, **fields) -> None:
        """Sets a character's attention parameters: ``params``, or its current ones with
        ``fields`` changed (``set_character_params(id, attention_fraction=0.5)``)."""
        if params is None:
            params = _fill(self.character_params(character), fields, "cg_character_params")
        check(
            lib.cg_crowd_set_character_params(self.handle, character, byref(params)),
            "cg_crowd_set_character_params",
        )

    def set_viewer(self, position, impact: float = 1.0) -> int:
        """Adds the viewer (user or camera) as an entity characters may look at, or moves
        it; returns its id."""
        out = c_uint32(n.CG_NO_TARGET)
        check(
            lib.cg_crowd_set_viewer(
                self.handle, byref(a.vec3(position, "position")), impact, byref(out)
            ),
            "cg_crowd_set_viewer",
        )
        return out.value

    def set_attention_period(self, character: int, period: int) -> None:
        """Updates ``character``'s attention every ``period`` steps (1 to 64; 0: the crowd's
        level of detail)."""
        check(
            lib.cg_crowd_set_attention_period(self.handle, character, period),
            "cg_crowd_set_attention_period",
        )

    def set_impact(self, entity: int, impact: float) -> None:
        check(lib.cg_crowd_set_impact(self.handle, entity, impact), "cg_crowd_set_impact")

    # --- every frame ------------------------------------------------------------------------

    def push_frame(self, t: float, states) -> None:
        """Pushes entity states at time ``t``: a numpy array of ``ENTITY_STATE_DTYPE``
        (see ``entity_states``) or a ctypes array of ``EntityState`` (both without a copy),
        or a sequence of ``EntityState``."""
        keep, pointer, count = a.records_in(states, n.EntityState, "states")
        check(lib.cg_crowd_push_frame(self.handle, t, pointer, count), "cg_crowd_push_frame")
        del keep

    def step(self, dt: float) -> None:
        """Attention and gaze IK for every character, ``dt`` seconds after the last step."""
        check(lib.cg_crowd_step(self.handle, dt), "cg_crowd_step")

    def begin_step(self, dt: float) -> None:
        """Begins a step split into ranges (``step_range``), ``dt`` seconds after the last."""
        check(lib.cg_crowd_begin_step(self.handle, dt), "cg_crowd_begin_step")

    def step_range(self, first: int, count: int) -> None:
        """Steps characters ``first .. first + count`` of the open step, in the crowd's
        storage order (not ``read_gaze``'s: split ``0 .. character_count()`` any way). ctypes
        releases the GIL during the call, so Python threads may step disjoint ranges in
        parallel."""
        check(lib.cg_crowd_step_range(self.handle, first, count), "cg_crowd_step_range")

    def end_step(self) -> None:
        """Ends the open step, stepping the characters no range covered."""
        check(lib.cg_crowd_end_step(self.handle), "cg_crowd_end_step")

    def read_gaze(self, out=None) -> np.ndarray:
        """Where each character looks: a record array of ``GAZE_INFO_DTYPE`` (one per
        character, in character order), or ``out``'s first rows."""
        count = self.character_count() if out is None else out.size
        target = a.RecordsOut(out, count, n.GazeInfo, "out")
        written = c_size_t()
        check(
            lib.cg_crowd_read_gaze(
                self.handle,
                a.pointer(target.buffer, n.GazeInfo),
                target.buffer.size,
                byref(written),
            ),
            "cg_crowd_read_gaze",
        )
        return target.result(written.value)

    def _range(self, first: int, count: int | None) -> tuple[int, int]:
        if count is None:
            count = self.character_count() - first
        return first, count

    def joint_total(self, first: int = 0, count: int | None = None) -> int:
        """Joints of characters ``first .. first + count`` together (all by default)."""
        first, count = self._range(first, count)
        out = c_size_t()
        check(
            lib.cg_crowd_joint_total(self.handle, first, count, byref(out)), "cg_crowd_joint_total"
        )
        return out.value

    def _read_quats(self, function, name, first, count, out):
        first, count = self._range(first, count)
        total = self.joint_total(first, count)
        target = a.FloatOut(out, total, 4, "out")
        check(function(self.handle, first, count, a.pointer(target.buffer, n.Quat), total), name)
        return target.result()

    def read_joints(self, first: int = 0, count: int | None = None, out=None) -> np.ndarray:
        """The final local rotations (``base * delta``, x y z w) of the chain joints of
        characters ``first .. first + count``, bottom to top, chain after chain: a
        ``(joints, 4)`` float32 array, or ``out`` written in place."""
        return self._read_quats(lib.cg_crowd_read_joints, "cg_crowd_read_joints", first, count, out)

    def read_joint_deltas(self, first: int = 0, count: int | None = None, out=None) -> np.ndarray:
        """The gaze's delta rotations alone (``final = base * delta``), as ``read_joints``."""
        return self._read_quats(
            lib.cg_crowd_read_joint_deltas, "cg_crowd_read_joint_deltas", first, count, out
        )

    def read_eyes(self, first: int = 0, count: int | None = None, out=None) -> np.ndarray:
        """Eye origins and directions (world, your units): a record array of
        ``EYE_INFO_DTYPE``, one per character."""
        first, count = self._range(first, count)
        target = a.RecordsOut(out, count, n.EyeInfo, "out")
        check(
            lib.cg_crowd_read_eyes(
                self.handle, first, count, a.pointer(target.buffer, n.EyeInfo), count
            ),
            "cg_crowd_read_eyes",
        )
        return target.result()

    def set_base_pose(self, character: int, local) -> None:
        """The animated local rotations of a character's chain joints (``(joints, 4)``, x y z
        w, bottom to top); a float32 C-contiguous array is passed without a copy."""
        quats = a.float_rows(local, n.Quat, "local")
        check(
            lib.cg_crowd_set_base_pose(
                self.handle, character, a.pointer(quats, n.Quat), len(quats)
            ),
            "cg_crowd_set_base_pose",
        )

    def set_base_poses(self, characters, local) -> None:
        """Base poses of many characters, their joints packed in the order of ``characters``."""
        ids = np.ascontiguousarray(np.asarray(characters, dtype=np.uint32).reshape(-1))
        quats = a.float_rows(local, n.Quat, "local")
        check(
            lib.cg_crowd_set_base_poses(
                self.handle,
                a.pointer(ids, c_uint32),
                ids.size,
                a.pointer(quats, n.Quat),
                len(quats),
            ),
            "cg_crowd_set_base_poses",
        )

    def set_gaze_target(
        self,
        character: int,
        point=None,
        *,
        entity=None,
        priority=n.CG_GAZE_PRIORITY_OVERRIDE,
        target=None,
    ) -> None:
        """An explicit gaze target: a ``point`` (3 numbers), an ``entity`` id followed as it
        moves, or a ready ``GazeTarget``. ``priority``: ``GAZE_PRIORITY_OVERRIDE`` or
        ``GAZE_PRIORITY_WHEN_IDLE``."""
        if target is None:
            if (point is None) == (entity is None):
                raise TypeError("give exactly one of point and entity")
            if point is not None:
                target = gaze_target(kind=n.CG_GAZE_TARGET_POINT, point=point, priority=priority)
            else:
                target = gaze_target(kind=n.CG_GAZE_TARGET_ENTITY, entity=entity, priority=priority)
        check(
            lib.cg_crowd_set_gaze_target(self.handle, character, byref(target)),
            "cg_crowd_set_gaze_target",
        )

    def clear_gaze_target(self, character: int) -> None:
        check(lib.cg_crowd_clear_gaze_target(self.handle, character), "cg_crowd_clear_gaze_target")

    # --- tools and offline planning ---------------------------------------------------------

    def score(self, character: int, entity: int) -> n.ScoreBreakdown:
        """Every intermediate of the score of ``entity`` for ``character``."""
        out = n.ScoreBreakdown()
        check(lib.cg_crowd_score(self.handle, character, entity, byref(out)), "cg_crowd_score")
        return out

    def plan(self) -> None:
        """Plans attention offline over the recorded frames (``max_recorded_states``)."""
        check(lib.cg_crowd_plan(self.handle), "cg_crowd_plan")

    def clear_plan(self) -> None:
        check(lib.cg_crowd_clear_plan(self.handle), "cg_crowd_clear_plan")

    def read_constraints(self, character: int) -> np.ndarray:
        """A character's planned constraints, in time order: a record array of
        ``CONSTRAINT_DTYPE`` (entity, s_max, begin, end)."""
        total = c_size_t()
        check(
            lib.cg_crowd_read_constraints(self.handle, character, None, 0, byref(total)),
            "cg_crowd_read_constraints",
        )
        out = np.zeros(total.value, dtype=a.CONSTRAINT_DTYPE)
        check(
            lib.cg_crowd_read_constraints(
                self.handle, character, a.pointer(out, n.Constraint), out.size, byref(total)
            ),
            "cg_crowd_read_constraints",
        )
        return out
