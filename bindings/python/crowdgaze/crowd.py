"""``crowdgaze.Crowd``: attention and gaze IK for a crowd (the ``cg_crowd`` handle).

Every method converts and checks all its arguments first (``crowdgaze._checks``,
``crowdgaze._arrays``: wrong types raise ``TypeError``, integers out of their C range
``OverflowError``, wrong shapes ``ValueError``, each naming the argument), then makes its
C calls holding the crowd's guard (see ``crowdgaze._owner``), and raises
``crowdgaze.Error`` if the library refuses the call, which then changed nothing.
"""

from __future__ import annotations

from typing import Any, NamedTuple
from ctypes import POINTER, byref, c_size_t, c_uint32, sizeof

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _exceptions as e
from . import _arrays as a
from . import _checks as c
from . import _native as n
from ._errors import check
from ._library import lib
from ._owner import HandleOwner


def _new(ctype: Any, init: Any, init_name: str, fields: dict[str, Any], where: str) -> Any:
    """A ``ctype`` filled by the library's ``init``, then ``fields`` (checked first)."""
    converted = a.struct_fields(ctype, fields, where)
    struct = ctype(struct_size=sizeof(ctype))
    check(init(byref(struct)), init_name)
    return a.fill(struct, converted)


def crowd_config(**fields: Any) -> n.CrowdConfig:
    """A ``CrowdConfig`` with the library's defaults (``cg_crowd_config_init``), then
    ``fields`` set (``crowd_config(max_characters=100, seed=7)``). The fields are the
    header's, documented there: blinks, for instance, are ``blink_rate`` (per minute),
    ``blink_rate_spread``, ``evoked_blink_min_amplitude``, ``evoked_blink_full_amplitude``
    (radians), ``evoked_blink_probability`` and ``lid_gain``, and ``eye_motion`` is an
    ``EyeMotion``. Values out of range are refused by ``Crowd``, naming the field."""
    return _new(n.CrowdConfig, lib.cg_crowd_config_init, "cg_crowd_config_init", fields,
                "crowd_config")


def street_config(**fields: Any) -> n.CrowdConfig:
    """A ``CrowdConfig`` with the street preset (``cg_crowd_config_init_street``): the
    defaults, but ``max_distance`` 17 m (walkers notice each other as far away as they were
    measured to) and gaze following on (``follow_enabled`` 1, Milgram's strength); then
    ``fields`` set. Give the characters ``AttentionModel.STREET``
    (``crowd.add_character(position, attention_model=cg.AttentionModel.STREET)``). The
    street model's settings are the ``street_*`` fields, gaze following's the ``follow_*``
    ones (see the header). Like ``crowd_config`` it is in metres: with another
    ``units_per_metre``, give the lengths (``max_distance``, ``follow_distance``,
    ``street_civil_distance``, ``street_path_look_distance``, ``street_civil_look_distance``
    ...) in those units too."""
    return _new(n.CrowdConfig, lib.cg_crowd_config_init_street, "cg_crowd_config_init_street",
                fields, "street_config")


class Following(NamedTuple):
    """What ``Crowd.read_following`` says of a character: the point (world, the crowd's
    units and axes) it glances at now because others look there, or None, and how many
    such glances it has started."""

    point: tuple[float, float, float] | None
    glances: int


def character_desc(**fields: Any) -> n.CharacterDesc:
    """A ``CharacterDesc`` with defaults, then ``fields`` (``position`` a 3-sequence,
    ``chain`` a ``ChainDesc`` or None)."""
    return _new(n.CharacterDesc, lib.cg_character_desc_init, "cg_character_desc_init",
                fields, "character_desc")


def object_desc(**fields: Any) -> n.ObjectDesc:
    """An ``ObjectDesc`` with defaults, then ``fields``."""
    return _new(n.ObjectDesc, lib.cg_object_desc_init, "cg_object_desc_init", fields,
                "object_desc")


def gaze_target(**fields: Any) -> n.GazeTarget:
    """A ``GazeTarget`` with defaults (a point target, overriding), then ``fields``."""
    return _new(n.GazeTarget, lib.cg_gaze_target_init, "cg_gaze_target_init", fields,
                "gaze_target")


def chain_desc_human(up_axis: int = n.Axis.POSITIVE_Y, forward_axis: int = n.Axis.POSITIVE_Z) -> n.ChainDesc:
    """The human gaze chain (5 spine, 2 cervical, head, 2 eyes; metres) for these axes."""
    where = "chain_desc_human"
    up_axis = c.integer(up_axis, where, "up_axis")
    forward_axis = c.integer(forward_axis, where, "forward_axis")
    desc = n.ChainDesc(struct_size=sizeof(n.ChainDesc))
    check(
        lib.cg_chain_desc_init_human(byref(desc), up_axis, forward_axis),
        "cg_chain_desc_init_human",
    )
    return desc


def entity_states(
    ids: ArrayLike, positions: a.Numbers | None = None, flags: int = n.CG_STATE_HEADING_FROM_MOTION
) -> NDArray[Any]:
    """A numpy record array of ``cg_entity_state`` (``ENTITY_STATE_DTYPE``) for ``ids``, each
    initialised by ``cg_entity_state_init``, with ``flags`` and, if given, ``positions``
    (``(n, 3)``). Set ``states["position"]`` (an ``(n, 3)`` float32 view) each frame and pass
    the array to ``Crowd.push_frame``: it goes to C without a copy. Who talks changes from
    frame to frame too: set ``cg.CG_STATE_TALKING`` in a talking entity's flags
    (``states["flags"][i] |= cg.CG_STATE_TALKING``) and clear it when it stops
    (``states["flags"][i] &= ~cg.CG_STATE_TALKING``); see ``Crowd.set_conversation``."""
    where = "entity_states"
    ids = a.unsigned(ids, where, "ids")
    flags = c.integer(flags, where, "flags")
    if positions is not None:
        positions = a.float_rows(positions, n.Vec3, where, "positions")
        if len(positions) != ids.size:
            raise e.value_error(
                f"{where}: positions holds {len(positions)} positions for {ids.size} ids"
            )
    template = n.EntityState(struct_size=sizeof(n.EntityState))
    check(lib.cg_entity_state_init(byref(template)), "cg_entity_state_init")
    states = np.zeros(ids.size, dtype=a.ENTITY_STATE_DTYPE)
    states["struct_size"] = template.struct_size
    states["heading"] = template.heading
    states["id"] = ids
    states["flags"] = flags
    if positions is not None:
        states["position"] = positions
    return states


def _character_count(handle: Any) -> int:
    out = c_size_t()
    check(lib.cg_crowd_character_count(handle, byref(out)), "cg_crowd_character_count")
    return out.value


def _read_gaze(handle: Any, out: np.ndarray) -> None:
    """Fills ``out`` (one ``GAZE_INFO_DTYPE`` record per character) by
    ``cg_crowd_read_gaze``."""
    written = c_size_t()
    check(
        lib.cg_crowd_read_gaze(handle, a.pointer(out, n.GazeInfo), out.size, byref(written)),
        "cg_crowd_read_gaze",
    )


def _joint_total(handle: Any, first: int, count: int) -> int:
    out = c_size_t()
    check(lib.cg_crowd_joint_total(handle, first, count, byref(out)), "cg_crowd_joint_total")
    return out.value


def _range(handle: Any, first: int, count: int | None) -> tuple[int, int]:
    """``(first, count)``, ``count`` defaulting to the characters from ``first`` on."""
    if count is None:
        count = max(_character_count(handle) - first, 0)
    return first, count


def _optional_count(count: Any, where: str) -> int | None:
    return None if count is None else c.integer(count, where, "count")


class Crowd(HandleOwner):
    """A crowd of characters and the objects they may look at.

    ``Crowd(config)`` or ``Crowd(max_characters=..., seed=...)`` (fields of
    ``crowd_config``; with ``config`` too, they change a copy of it). Release it with
    ``close()`` or a ``with`` block (or let it be collected). Every method raises
    ``crowdgaze.Error`` on failure; a failed call changes nothing.

    Threads: reads (``read_*``, ``score``, ``character_count``, ...), ``step_range`` and
    ``push_range`` may run on several threads at once; calls that change the crowd take
    turns. ``close()`` from another thread waits for the calls in flight. A crowd cannot be
    copied or pickled, and ``__init__`` runs once (see ``crowdgaze._owner``).
    """

    _kind = "crowd"
    _destroy: Any = lib.cg_crowd_destroy

    def __init__(self, config: n.CrowdConfig | None = None, **fields: Any):
        where = "Crowd"
        self._refuse_reinit(where)
        if config is None:
            config = _new(n.CrowdConfig, lib.cg_crowd_config_init, "cg_crowd_config_init",
                          fields, where)
        else:
            c.instance(config, n.CrowdConfig, where, "config")
            converted = a.struct_fields(n.CrowdConfig, fields, where)
            config = a.fill(n.CrowdConfig.from_buffer_copy(config), converted)
        handle = POINTER(n.CrowdHandle)()
        check(lib.cg_crowd_create(byref(config), byref(handle)), "cg_crowd_create")
        self._adopt(handle, where)
        self._max_characters = config.max_characters

    def _describe(self) -> str:
        return f"{self.character_count()} of {self._max_characters} characters"

    # --- setup ------------------------------------------------------------------------------

    @property
    def config(self) -> n.CrowdConfig:
        """The settings the crowd was created with: a read-only copy (they cannot change;
        assigning a field raises ``crowdgaze.FieldError``). ``Crowd(crowd.config, seed=5)``
        makes a crowd with the same settings but a field."""
        config = n.CrowdConfig(struct_size=sizeof(n.CrowdConfig))
        with self._call("Crowd.config") as handle:
            check(lib.cg_crowd_get_config(handle, byref(config)), "cg_crowd_get_config")
        config._freeze("Crowd.config: the settings a crowd was created with")
        return config

    def add_character(
        self,
        position: a.Numbers | None = None,
        heading: float | None = None,
        *,
        desc: n.CharacterDesc | None = None,
        chain: n.ChainDesc | None = None,
        **fields: Any,
    ) -> int:
        """Adds a character; returns its id. Either a ready ``desc`` (``CharacterDesc``) or
        ``position`` (default the origin), ``heading`` (default 0), ``chain`` (a
        ``ChainDesc``, default the human chain) and other ``CharacterDesc`` fields."""
        where = "Crowd.add_character"
        if desc is not None:
            if position is not None or heading is not None or chain is not None or fields:
                raise e.type_error(f"{where}: give desc, or position, heading, chain and fields; "
                                f"not both")
            c.instance(desc, n.CharacterDesc, where, "desc")
        else:
            values = dict(fields)
            for name, value in (("position", position), ("heading", heading), ("chain", chain)):
                if value is not None:
                    values[name] = value
            converted = a.struct_fields(n.CharacterDesc, values, where)
            desc = n.CharacterDesc(struct_size=sizeof(n.CharacterDesc))
            check(lib.cg_character_desc_init(byref(desc)), "cg_character_desc_init")
            a.fill(desc, converted)
        out = c_uint32()
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_crowd_add_character(handle, byref(desc), byref(out)),
                "cg_crowd_add_character",
            )
        return out.value

    def add_object(self, position: a.Numbers | None = None, *, desc: n.ObjectDesc | None = None, **fields: Any) -> int:
        """Adds a scene object; returns its id. Either a ready ``desc`` (``ObjectDesc``) or
        ``position`` (default the origin) and ``fields`` (heading, look_at_height, impact)."""
        where = "Crowd.add_object"
        if desc is not None:
            if position is not None or fields:
                raise e.type_error(f"{where}: give desc, or position and fields; not both")
            c.instance(desc, n.ObjectDesc, where, "desc")
        else:
            values = dict(fields)
            if position is not None:
                values["position"] = position
            desc = _new(n.ObjectDesc, lib.cg_object_desc_init, "cg_object_desc_init", values,
                        where)
        out = c_uint32()
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_add_object(handle, byref(desc), byref(out)), "cg_crowd_add_object")
        return out.value

    def remove_entity(self, entity: int) -> None:
        """Removes a character, an object or the viewer."""
        where = "Crowd.remove_entity"
        entity = c.integer(entity, where, "entity")
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_remove_entity(handle, entity), "cg_crowd_remove_entity")

    def character_count(self) -> int:
        """The number of characters (``len(crowd)`` too)."""
        with self._call("Crowd.character_count") as handle:
            return _character_count(handle)

    def __len__(self) -> int:
        """The number of characters."""
        return self.character_count()

    def character_params(self, character: int) -> n.CharacterParams:
        """A copy of ``character``'s attention parameters; change it and pass it to
        ``set_character_params`` (or give that the changed fields)."""
        where = "Crowd.character_params"
        character = c.integer(character, where, "character")
        out = n.CharacterParams(struct_size=sizeof(n.CharacterParams))
        with self._call(where) as handle:
            check(
                lib.cg_crowd_get_character_params(handle, character, byref(out)),
                "cg_crowd_get_character_params",
            )
        return out

    def set_character_params(self, character: int, params: n.CharacterParams | None = None, **fields: Any) -> None:
        """Sets a character's attention parameters: ``params``, or its current ones with
        ``fields`` changed (``set_character_params(id, attention_fraction=0.5)``)."""
        where = "Crowd.set_character_params"
        character = c.integer(character, where, "character")
        if params is not None:
            if fields:
                raise e.type_error(f"{where}: give params or fields, not both")
            c.instance(params, n.CharacterParams, where, "params")
            converted = None
        else:
            converted = a.struct_fields(n.CharacterParams, fields, where)
        with self._call(where, exclusive=True) as handle:
            if converted is not None:
                params = n.CharacterParams(struct_size=sizeof(n.CharacterParams))
                check(
                    lib.cg_crowd_get_character_params(handle, character, byref(params)),
                    "cg_crowd_get_character_params",
                )
                a.fill(params, converted)
            assert params is not None
            check(
                lib.cg_crowd_set_character_params(handle, character, byref(params)),
                "cg_crowd_set_character_params",
            )

    def set_viewer(self, position: a.Numbers, impact: float = 1.0) -> int:
        """Adds the viewer (user or camera) as an entity characters may look at, or moves
        it; returns its id."""
        where = "Crowd.set_viewer"
        position = a.vec3(position, where, "position")
        impact = c.real(impact, where, "impact")
        out = c_uint32(n.CG_NO_TARGET)
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_crowd_set_viewer(handle, byref(position), impact, byref(out)),
                "cg_crowd_set_viewer",
            )
        return out.value

    def set_attention_period(self, character: int, period: int) -> None:
        """Updates ``character``'s attention every ``period`` steps (1 to 64; 0: the crowd's
        level of detail)."""
        where = "Crowd.set_attention_period"
        character = c.integer(character, where, "character")
        period = c.integer(period, where, "period")
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_crowd_set_attention_period(handle, character, period),
                "cg_crowd_set_attention_period",
            )

    def set_impact(self, entity: int, impact: float) -> None:
        """How much ``entity`` (a character, an object or the viewer) draws attention."""
        where = "Crowd.set_impact"
        entity = c.integer(entity, where, "entity")
        impact = c.real(impact, where, "impact")
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_set_impact(handle, entity, impact), "cg_crowd_set_impact")

    # --- every frame ------------------------------------------------------------------------

    def push_frame(self, t: float, states: a.Numbers) -> None:
        """Pushes entity states at time ``t``: a numpy array of ``ENTITY_STATE_DTYPE``
        (see ``entity_states``) or a ctypes array of ``EntityState`` (both without a copy),
        or a sequence (list, tuple) of ``EntityState``."""
        where = "Crowd.push_frame"
        t = c.real(t, where, "t", single=False)
        keep, pointer, count = a.records_in(states, n.EntityState, where, "states")
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_push_frame(handle, t, pointer, count), "cg_crowd_push_frame")
        del keep

    def begin_push(self, t: float) -> None:
        """Begins a frame pushed in parts (``push_range``) at time ``t``, not earlier than the
        last frame. The parts together give the same crowd as one ``push_frame``."""
        where = "Crowd.begin_push"
        t = c.real(t, where, "t", single=False)
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_begin_push(handle, t), "cg_crowd_begin_push")

    def push_range(self, states: a.Numbers) -> None:
        """Pushes a part of the open push's states (as ``push_frame`` takes them); each
        entity once per push. ctypes releases the GIL during the call, so Python threads may
        push their own entities in parallel."""
        where = "Crowd.push_range"
        keep, pointer, count = a.records_in(states, n.EntityState, where, "states")
        with self._call(where) as handle:  # shared: C allows concurrent ranges
            check(lib.cg_crowd_push_range(handle, pointer, count), "cg_crowd_push_range")
        del keep

    def end_push(self) -> None:
        """Ends the open push (after the ``push_range`` calls in flight have returned):
        entities no part pushed keep their last state."""
        where = "Crowd.end_push"
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_end_push(handle), "cg_crowd_end_push")

    def step(self, dt: float) -> None:
        """Attention and gaze IK for every character, ``dt`` seconds after the last step."""
        where = "Crowd.step"
        dt = c.real(dt, where, "dt")
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_step(handle, dt), "cg_crowd_step")

    def begin_step(self, dt: float) -> None:
        """Begins a step split into ranges (``step_range``), ``dt`` seconds after the last."""
        where = "Crowd.begin_step"
        dt = c.real(dt, where, "dt")
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_begin_step(handle, dt), "cg_crowd_begin_step")

    def step_range(self, first: int, count: int) -> None:
        """Steps characters ``first .. first + count`` of the open step, in the crowd's
        storage order (not ``read_gaze``'s: split ``0 .. character_count()`` any way). ctypes
        releases the GIL during the call, so Python threads may step disjoint ranges in
        parallel."""
        where = "Crowd.step_range"
        first = c.integer(first, where, "first")
        count = c.integer(count, where, "count")
        with self._call(where) as handle:  # shared: C allows concurrent ranges
            check(lib.cg_crowd_step_range(handle, first, count), "cg_crowd_step_range")

    def end_step(self) -> None:
        """Ends the open step, stepping the characters no range covered (after the
        ``step_range`` calls in flight have returned)."""
        where = "Crowd.end_step"
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_end_step(handle), "cg_crowd_end_step")

    def read_gaze(self, out: a.Out = None) -> NDArray[Any]:
        """Where each character looks: a record array of ``GAZE_INFO_DTYPE``, one per
        character in character order (``rows_of`` maps ids to its rows); or ``out``
        (exactly ``(characters,)`` of it) written in place."""
        where = "Crowd.read_gaze"
        if out is not None:
            a.check_out(out, a.GAZE_INFO_DTYPE, where, ndim=1)
        with self._call(where) as handle:
            out = a.shaped(out, a.GAZE_INFO_DTYPE, (_character_count(handle),), where)
            _read_gaze(handle, out)
        return out

    def rows_of(self, characters: ArrayLike) -> NDArray[Any]:
        """The rows of ``characters`` (ids: any sequence of integers or an integer array) in
        what ``read_gaze``, ``read_eyes`` and ``read_eyelids`` return, as an ``intp`` array
        to index them with (``gaze[crowd.rows_of(ids)]``); ``read_joints(row, 1)`` reads
        one character's joints. Rows are the crowd's character order, which removing a
        character changes (the last one takes its place): map ids to rows again after a
        removal. An id that is no character of the crowd raises ``NotFoundError`` (a
        ``LookupError``)."""
        where = "Crowd.rows_of"
        return self._rows(a.unsigned(characters, where, "characters"), where)

    def row_of(self, character: int) -> int:
        """The row of ``character`` in what ``read_gaze``, ``read_eyes`` and
        ``read_eyelids`` return (see ``rows_of``)."""
        where = "Crowd.row_of"
        character = c.integer(character, where, "character")
        return int(self._rows(np.array([character], np.uint32), where)[0])

    def _rows(self, wanted: np.ndarray, where: str) -> NDArray[Any]:
        with self._call(where) as handle:
            gaze = np.empty(_character_count(handle), a.GAZE_INFO_DTYPE)
            _read_gaze(handle, gaze)
        order = gaze["character"]
        rows = np.zeros(wanted.size, np.intp)
        if order.size:
            by_id = np.argsort(order, kind="stable")
            found = np.searchsorted(order, wanted, sorter=by_id)
            rows = by_id[np.minimum(found, order.size - 1)].astype(np.intp)
        missing = np.flatnonzero(order[rows] != wanted) if order.size else np.arange(wanted.size)
        if missing.size:
            unknown = int(wanted[missing[0]])
            raise e.not_found_error(f"{where}: {unknown} is not a character of this crowd")
        return rows

    def joint_total(self, first: int = 0, count: int | None = None) -> int:
        """Joints of characters ``first .. first + count`` together (all by default)."""
        where = "Crowd.joint_total"
        first = c.integer(first, where, "first")
        count = _optional_count(count, where)
        with self._call(where) as handle:
            return _joint_total(handle, *_range(handle, first, count))

    def _read_quats(
        self, function: Any, name: str, where: str, first: int, count: int | None, out: a.Out
    ) -> NDArray[Any]:
        first = c.integer(first, where, "first")
        count = _optional_count(count, where)
        if out is not None:
            a.check_out(out, a.FLOAT32, where, ndim=2)
        with self._call(where) as handle:
            first, count = _range(handle, first, count)
            total = _joint_total(handle, first, count)
            out = a.shaped(out, a.FLOAT32, (total, 4), where)
            check(function(handle, first, count, a.pointer(out, n.Quat), total), name)
        return out

    def read_joints(self, first: int = 0, count: int | None = None, out: a.Out = None) -> NDArray[Any]:
        """The final local rotations (``base * delta``, x y z w) of the chain joints of
        characters ``first .. first + count``, bottom to top, chain after chain: a
        ``(joints, 4)`` float32 array, or ``out`` (exactly that) written in place."""
        return self._read_quats(
            lib.cg_crowd_read_joints, "cg_crowd_read_joints", "Crowd.read_joints", first,
            count, out,
        )

    def read_joint_deltas(self, first: int = 0, count: int | None = None, out: a.Out = None) -> NDArray[Any]:
        """The gaze's delta rotations alone (``final = base * delta``), as ``read_joints``."""
        return self._read_quats(
            lib.cg_crowd_read_joint_deltas, "cg_crowd_read_joint_deltas",
            "Crowd.read_joint_deltas", first, count, out,
        )

    def _read_records(
        self,
        function: Any,
        name: str,
        where: str,
        ctype: Any,
        first: int,
        count: int | None,
        out: a.Out,
    ) -> NDArray[Any]:
        """One ``ctype`` record per character of ``first .. first + count`` (all from
        ``first`` by default), read by ``function`` into a new array or into ``out``
        (exactly ``(count,)`` of the record dtype)."""
        dtype = a.RECORD_DTYPES[ctype]
        first = c.integer(first, where, "first")
        count = _optional_count(count, where)
        if out is not None:
            a.check_out(out, dtype, where, ndim=1)
        with self._call(where) as handle:
            first, count = _range(handle, first, count)
            out = a.shaped(out, dtype, (count,), where)
            check(function(handle, first, count, a.pointer(out, ctype), count), name)
        return out

    def read_eyes(self, first: int = 0, count: int | None = None, out: a.Out = None) -> NDArray[Any]:
        """Eye origins and directions (world, your units): a record array of
        ``EYE_INFO_DTYPE``, one per character; or ``out`` (exactly ``(count,)`` of it)."""
        return self._read_records(
            lib.cg_crowd_read_eyes, "cg_crowd_read_eyes", "Crowd.read_eyes", n.EyeInfo, first,
            count, out,
        )

    def read_eyelids(self, first: int = 0, count: int | None = None, out: a.Out = None) -> NDArray[Any]:
        """The eyelids of characters ``first .. first + count`` (all from ``first`` by
        default) after the last step, in ``read_gaze``'s order: a record array of
        ``EYELIDS_DTYPE``, one per character, or ``out`` (exactly ``(count,)`` of it) written
        in place. ``left_closure`` and ``right_closure`` go from 0 (open) to 1 (closed, a
        blink; both eyes blink together); ``left_lid_pitch`` and ``right_lid_pitch`` are the
        upper lids' pitches in the head's frame (radians, positive up: ``lid_gain`` times the
        eye's pitch), the closure coming on top. Blinks follow the config's ``blink_rate``
        and ``evoked_blink_*`` fields and are the same in every run."""
        return self._read_records(
            lib.cg_crowd_read_eyelids, "cg_crowd_read_eyelids", "Crowd.read_eyelids",
            n.Eyelids, first, count, out,
        )

    def set_base_pose(self, character: int, local: a.Numbers) -> None:
        """The animated local rotations of a character's chain joints (``(joints, 4)``, x y z
        w, bottom to top); a float32 C-contiguous array is passed without a copy."""
        where = "Crowd.set_base_pose"
        character = c.integer(character, where, "character")
        quats = a.float_rows(local, n.Quat, where, "local")
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_crowd_set_base_pose(handle, character, a.pointer(quats, n.Quat), len(quats)),
                "cg_crowd_set_base_pose",
            )

    def set_base_poses(self, characters: ArrayLike, local: a.Numbers) -> None:
        """Base poses of many characters, their joints packed in the order of ``characters``
        (all or nothing)."""
        where = "Crowd.set_base_poses"
        ids = a.unsigned(characters, where, "characters")
        quats = a.float_rows(local, n.Quat, where, "local")
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_crowd_set_base_poses(
                    handle, a.pointer(ids, c_uint32), ids.size, a.pointer(quats, n.Quat),
                    len(quats),
                ),
                "cg_crowd_set_base_poses",
            )

    def set_gaze_target(
        self, character: int, point: a.Numbers | None = None,
        *,
        entity: int | None = None,
        priority: int | None = None,
        target: n.GazeTarget | None = None,
    
    ) -> None:
        """An explicit gaze target: a ``point`` (3 numbers), an ``entity`` id followed as it
        moves, or a ready ``GazeTarget``. ``priority``: ``GAZE_PRIORITY_OVERRIDE`` (default)
        or ``GAZE_PRIORITY_WHEN_IDLE``."""
        where = "Crowd.set_gaze_target"
        character = c.integer(character, where, "character")
        if target is not None:
            if point is not None or entity is not None or priority is not None:
                raise e.type_error(f"{where}: give target, or point or entity (and priority); "
                                f"not both")
            c.instance(target, n.GazeTarget, where, "target")
        else:
            if (point is None) == (entity is None):
                raise e.type_error(f"{where}: give exactly one of point and entity")
            fields: dict[str, Any] = {"priority": n.CG_GAZE_PRIORITY_OVERRIDE if priority is None else priority}
            if point is not None:
                fields.update(kind=n.CG_GAZE_TARGET_POINT, point=point)
            else:
                fields.update(kind=n.CG_GAZE_TARGET_ENTITY, entity=entity)
            target = _new(n.GazeTarget, lib.cg_gaze_target_init, "cg_gaze_target_init", fields,
                          where)
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_crowd_set_gaze_target(handle, character, byref(target)),
                "cg_crowd_set_gaze_target",
            )

    def clear_gaze_target(self, character: int) -> None:
        """Removes ``character``'s explicit gaze target: back to its own attention."""
        where = "Crowd.clear_gaze_target"
        character = c.integer(character, where, "character")
        with self._call(where, exclusive=True) as handle:
            check(lib.cg_crowd_clear_gaze_target(handle, character), "cg_crowd_clear_gaze_target")

    # --- conversations ----------------------------------------------------------------------

    def set_conversation(self, members: ArrayLike) -> int:
        """Makes ``members`` (2 to ``CG_MAX_CONVERSATION_MEMBERS`` character ids, as any
        sequence of integers or an integer array, each in no other conversation) a group
        standing together and talking; returns the group's id. From the next step its
        members look at each other as people in conversation do: listeners mostly at the
        member whose pushed state has ``CG_STATE_TALKING`` in its ``flags`` (see
        ``entity_states``), the speaker at its listeners now and then. Removing a member
        takes it out of the group; a group left with one member ends."""
        where = "Crowd.set_conversation"
        ids = a.unsigned(members, where, "members")
        out = c_uint32(n.CG_NO_TARGET)
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_crowd_set_conversation(
                    handle, a.pointer(ids, c_uint32), ids.size, byref(out)
                ),
                "cg_crowd_set_conversation",
            )
        return out.value

    def remove_conversation(self, group: int) -> None:
        """Ends conversation ``group``: its members go back to their own attention."""
        where = "Crowd.remove_conversation"
        group = c.integer(group, where, "group")
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_crowd_remove_conversation(handle, group), "cg_crowd_remove_conversation"
            )

    def conversation_of(self, character: int) -> int | None:
        """The id of the conversation ``character`` is in, or None if it is in none."""
        where = "Crowd.conversation_of"
        character = c.integer(character, where, "character")
        out = c_uint32(n.CG_NO_TARGET)
        with self._call(where) as handle:
            check(
                lib.cg_crowd_get_conversation(handle, character, byref(out)),
                "cg_crowd_get_conversation",
            )
        return None if out.value == n.CG_NO_TARGET else out.value

    # --- gaze following ----------------------------------------------------------------------

    def read_following(self, character: int) -> Following:
        """Whether ``character`` follows others' gaze now (``follow_enabled`` in the config):
        the point it glances at because people in its view stare there (characters whose
        overriding gaze target is a point or an object), or None, and its glances so far.
        A character with an overriding target of its own follows no one."""
        where = "Crowd.read_following"
        character = c.integer(character, where, "character")
        point = n.Vec3()
        following = c_uint32(0)
        glances = c_uint32(0)
        with self._call(where) as handle:
            check(
                lib.cg_crowd_read_following(
                    handle, character, byref(point), byref(following), byref(glances)
                ),
                "cg_crowd_read_following",
            )
        seen = (point.x, point.y, point.z) if following.value else None
        return Following(seen, glances.value)

    # --- tools and offline planning ---------------------------------------------------------

    def score(self, character: int, entity: int) -> n.ScoreBreakdown:
        """Every intermediate of the score of ``entity`` for ``character``."""
        where = "Crowd.score"
        character = c.integer(character, where, "character")
        entity = c.integer(entity, where, "entity")
        out = n.ScoreBreakdown()
        with self._call(where) as handle:
            check(lib.cg_crowd_score(handle, character, entity, byref(out)), "cg_crowd_score")
        return out

    def plan(self) -> None:
        """Plans attention offline over the recorded frames (``max_recorded_states``)."""
        with self._call("Crowd.plan", exclusive=True) as handle:
            check(lib.cg_crowd_plan(handle), "cg_crowd_plan")

    def clear_plan(self) -> None:
        """Leaves planned mode and forgets the recording; online stepping and pushing
        resume."""
        with self._call("Crowd.clear_plan", exclusive=True) as handle:
            check(lib.cg_crowd_clear_plan(handle), "cg_crowd_clear_plan")

    def read_constraints(self, character: int) -> NDArray[Any]:
        """A character's planned constraints, in time order: a record array of
        ``CONSTRAINT_DTYPE`` (entity, s_max, begin, end)."""
        where = "Crowd.read_constraints"
        character = c.integer(character, where, "character")
        total = c_size_t()
        with self._call(where) as handle:
            check(
                lib.cg_crowd_read_constraints(handle, character, None, 0, byref(total)),
                "cg_crowd_read_constraints",
            )
            out = np.zeros(total.value, dtype=a.CONSTRAINT_DTYPE)
            check(
                lib.cg_crowd_read_constraints(
                    handle, character, a.pointer(out, n.Constraint), out.size, byref(total)
                ),
                "cg_crowd_read_constraints",
            )
        return out
