"""The package's Python conventions: one exception hierarchy, checked structs, flags that
numpy takes, one rule for ``out=``, rows of ids, names and docs, packaging."""

import pickle

import numpy as np
import pytest

import crowdgaze as cg

# --- errors ----------------------------------------------------------------------------------

#: Status -> (the class it raises, the built-in exceptions that class also is).
ERROR_CLASSES = {
    cg.Status.NULL_ARGUMENT: (cg.InvalidArgumentError, (ValueError,)),
    cg.Status.INVALID_ARGUMENT: (cg.InvalidArgumentError, (ValueError,)),
    cg.Status.NON_FINITE: (cg.NonFiniteError, (ValueError,)),
    cg.Status.NOT_FOUND: (cg.NotFoundError, (LookupError,)),
    cg.Status.CAPACITY: (cg.CapacityError, (RuntimeError,)),
    cg.Status.BAD_STRUCT_SIZE: (cg.InvalidArgumentError, (ValueError,)),
    cg.Status.WRONG_STATE: (cg.WrongStateError, (RuntimeError,)),
    cg.Status.NOT_CONVERGED: (cg.NotConvergedError, (RuntimeError,)),
    cg.Status.INTERNAL: (cg.InternalError, (RuntimeError,)),
    cg.Status.OUT_OF_MEMORY: (cg.OutOfMemoryError, (MemoryError,)),
    cg.Status.POISONED: (cg.InternalError, (RuntimeError,)),
}


def test_every_failing_status_has_its_error_class():
    assert set(ERROR_CLASSES) == set(cg.Status) - {cg.Status.OK}
    for status, (cls, builtins) in ERROR_CLASSES.items():
        error = cg.Error(status, "why", "cg_f")
        assert type(error) is cls, status
        assert isinstance(error, cg.Error) and isinstance(error, builtins), status
        assert (error.status, error.message, error.function) == (status, "why", "cg_f")
        assert str(error) == "cg_f: why"
        again = pickle.loads(pickle.dumps(error))
        assert type(again) is cls and again.status == status and str(again) == str(error)
    assert type(cg.Error(12345, "")) is cg.Error


def test_library_errors_are_the_matching_builtins():
    crowd = cg.Crowd(max_characters=1)
    me = crowd.add_character()
    with pytest.raises(LookupError) as info:
        crowd.remove_entity(1234)
    assert isinstance(info.value, cg.NotFoundError)
    assert info.value.function == "cg_crowd_remove_entity"
    with pytest.raises(ValueError) as info:
        crowd.step(float("nan"))
    assert isinstance(info.value, cg.NonFiniteError) and info.value.status == cg.Status.NON_FINITE
    with pytest.raises(ValueError) as info:
        crowd.step(-1.0)
    assert isinstance(info.value, cg.InvalidArgumentError)
    with pytest.raises(RuntimeError) as info:
        crowd.add_character()
    assert isinstance(info.value, cg.CapacityError)
    with pytest.raises(RuntimeError) as info:
        crowd.plan()
    assert isinstance(info.value, cg.WrongStateError)
    with pytest.raises(ValueError):
        cg.Crowd(max_characters=0)
    crowd.remove_entity(me)


def test_the_bindings_own_refusals_are_crowdgaze_errors_too():
    crowd = cg.Crowd(max_characters=1)
    cases = [
        (lambda: crowd.step("0.1"), cg.ArgumentTypeError, TypeError),
        (lambda: crowd.remove_entity(2**32), cg.ArgumentRangeError, OverflowError),
        (lambda: crowd.remove_entity(-1), cg.ArgumentRangeError, ValueError),
        (lambda: crowd.read_joints(out=np.zeros((3, 4))), cg.ArgumentTypeError, TypeError),
        (lambda: crowd.set_viewer((1, 2)), cg.InvalidArgumentError, ValueError),
    ]
    for call, cls, builtin in cases:
        with pytest.raises(cg.Error) as info:
            call()
        assert isinstance(info.value, cls) and isinstance(info.value, builtin), info.value
        assert info.value.function is None and info.value.message == str(info.value)
    crowd.close()
    with pytest.raises(cg.ClosedError) as info:
        crowd.step(0.1)
    assert isinstance(info.value, ValueError) and isinstance(info.value, cg.WrongStateError)
    assert info.value.status == cg.Status.WRONG_STATE


# --- checked structs -------------------------------------------------------------------------


def test_struct_fields_are_checked_on_assignment():
    config = cg.crowd_config()
    params = cg.CharacterParams()
    cases = [
        (lambda: setattr(config, "max_characters", 2**32 + 3), OverflowError, "max_characters"),
        (lambda: setattr(config, "seed", -1), OverflowError, "seed"),
        (lambda: setattr(config, "seed", 2**64), OverflowError, "seed"),
        (lambda: setattr(config, "units_per_metre", 1e300), OverflowError, "units_per_metre"),
        (lambda: setattr(config, "threads", 2.0), TypeError, "threads"),
        (lambda: setattr(config, "blink_rate", "fast"), TypeError, "blink_rate"),
        (lambda: setattr(params, "attention_model", 2**32 + 1), OverflowError, "attention_model"),
        (lambda: cg.CharacterParams(attention_model=-1), OverflowError, "attention_model"),
        (lambda: cg.CrowdConfig(4, 2**32), OverflowError, "max_characters"),
        (lambda: setattr(config, "max_charcters", 5), AttributeError, "max_charcters"),
        (lambda: setattr(cg.Vec3(), "x", "1"), TypeError, "x"),
    ]
    before = bytes(config), bytes(params)
    for call, builtin, name in cases:
        with pytest.raises(builtin) as info:
            call()
        assert isinstance(info.value, cg.Error) and name in str(info.value), info.value
    assert (bytes(config), bytes(params)) == before  # nothing was set
    config.seed = 2**64 - 1
    config.max_characters = np.uint32(7)
    config.field_of_view = np.float64(1.5)
    params.attention_model = cg.AttentionModel.BASELINE
    desc = cg.character_desc()
    desc.position = (1, 2, 3)
    assert (config.seed, config.max_characters, config.field_of_view) == (2**64 - 1, 7, 1.5)
    assert params.attention_model == cg.AttentionModel.BASELINE and tuple(desc.position) == (1, 2, 3)


def test_the_config_of_a_crowd_is_read_only():
    crowd = cg.Crowd(max_characters=3, seed=4)
    config = crowd.config
    with pytest.raises(AttributeError) as info:
        config.seed = 5  # would change nothing: the crowd keeps its settings
    assert isinstance(info.value, cg.FieldError) and "read-only" in str(info.value)
    assert crowd.config.seed == 4
    twin = cg.Crowd(crowd.config, seed=5)  # a new crowd from it, with a field changed
    assert (twin.config.seed, twin.config.max_characters) == (5, 3)
    copy = cg.CrowdConfig.from_buffer_copy(config)  # a writeable copy
    copy.seed = 6
    assert cg.Crowd(copy).config.seed == 6


def test_structs_and_crowds_have_a_repr():
    config = cg.crowd_config(max_characters=12)
    text = repr(config)
    assert text.startswith("CrowdConfig(struct_size=") and "max_characters=12" in text
    assert "up_axis=Axis.POSITIVE_Y" in text and "eye_motion=EyeMotion.PAPER" in text
    assert "attention_model=AttentionModel.CROWD" in repr(cg.CharacterParams())
    assert repr(cg.character_desc(position=(1, 2, 3))).endswith(
        "position=Vec3(1, 2, 3), chain=None, attention_model=AttentionModel.CROWD)"
    )
    crowd = cg.Crowd(config)
    crowd.add_character()
    assert repr(crowd) == "<crowdgaze.Crowd: 1 of 12 characters>"
    crowd.close()
    assert repr(crowd) == "<crowdgaze.Crowd: closed>"
    blender = cg.ViewBlender(joint_count=2, key_count=3)
    assert repr(blender) == "<crowdgaze.ViewBlender: 2 joints, 3 keys>"
    blender.close()
    assert repr(blender) == "<crowdgaze.ViewBlender: closed>"


# --- flags -----------------------------------------------------------------------------------


def test_state_flags_set_and_clear_bits_of_numpy_records():
    assert issubclass(cg.StateFlag, __import__("enum").IntFlag)
    assert cg.CG_STATE_TALKING is cg.StateFlag.TALKING is cg.STATE_TALKING
    assert 0 <= ~cg.CG_STATE_TALKING <= 2**32 - 1
    assert ~cg.CG_STATE_TALKING & cg.CG_STATE_TALKING == 0
    states = cg.entity_states([1, 2, 3], flags=cg.CG_STATE_HAS_VELOCITY | 8)
    assert states["flags"].dtype == np.uint32
    states["flags"][1] |= cg.CG_STATE_TALKING  # the documented way, element by element
    assert list(states["flags"]) == [10, 14, 10]
    states["flags"][1] &= ~cg.CG_STATE_TALKING
    assert list(states["flags"]) == [10, 10, 10]
    states["flags"] |= cg.CG_STATE_TALKING  # a whole column at once
    states["flags"] &= ~(cg.CG_STATE_HAS_VELOCITY | cg.CG_STATE_TALKING)
    assert list(states["flags"]) == [8, 8, 8] and states["flags"].dtype == np.uint32
    states["flags"] = cg.CG_STATE_TALKING
    assert list((states["flags"] & cg.CG_STATE_TALKING) != 0) == [True] * 3


# --- outputs and rows ------------------------------------------------------------------------


def test_every_reader_refuses_an_out_of_the_wrong_size():
    crowd = cg.Crowd(max_characters=4)
    for x in range(3):
        crowd.add_character((x, 0, 0))
    crowd.step(0.1)
    readers = [
        (crowd.read_gaze, cg.GAZE_INFO_DTYPE, 3),
        (crowd.read_eyes, cg.EYE_INFO_DTYPE, 3),
        (crowd.read_eyelids, cg.EYELIDS_DTYPE, 3),
    ]
    for read, dtype, rows in readers:
        for wrong in (rows - 1, rows + 1, 0):
            with pytest.raises(ValueError, match="out must have the shape") as info:
                read(out=np.zeros(wrong, dtype))
            assert isinstance(info.value, cg.InvalidArgumentError)
        out = np.zeros(rows, dtype)
        assert read(out=out) is out
    for read in (crowd.read_joints, crowd.read_joint_deltas):
        with pytest.raises(ValueError, match="out must have the shape"):
            read(out=np.zeros((31, 4), np.float32))


def test_rows_of_maps_ids_to_rows_before_and_after_a_removal():
    crowd = cg.Crowd(max_characters=5)
    ids = [crowd.add_character((x, 0, 0)) for x in range(4)]
    thing = crowd.add_object((0, 0, 5))
    crowd.step(0.1)
    assert list(crowd.rows_of(ids)) == [0, 1, 2, 3]
    crowd.remove_entity(ids[1])  # the last character takes its place
    crowd.step(0.1)
    gaze = crowd.read_gaze()
    rows = crowd.rows_of([ids[3], ids[0], ids[2]])
    assert rows.dtype == np.intp and list(gaze["character"][rows]) == [ids[3], ids[0], ids[2]]
    assert crowd.row_of(ids[3]) == rows[0]
    eyes = crowd.read_eyes()
    assert eyes["character"][crowd.row_of(ids[2])] == ids[2]
    joints = crowd.read_joints(crowd.row_of(ids[3]), 1)
    assert np.array_equal(joints, crowd.read_joints()[10 * rows[0]: 10 * rows[0] + 10])
    assert crowd.rows_of([]).size == 0
    for missing in (ids[1], thing, 999):
        with pytest.raises(LookupError, match=str(missing)) as info:
            crowd.rows_of([ids[0], missing])
        assert isinstance(info.value, cg.NotFoundError)
    with pytest.raises(cg.NotFoundError):
        cg.Crowd(max_characters=1).row_of(0)
