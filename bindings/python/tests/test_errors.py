"""Failures raise crowdgaze.Error with the status, the library's message and the function;
a failed call changes nothing."""

import ctypes
import threading

import numpy as np
import pytest

import crowdgaze as cg


def raises(status, function=None):
    class Expect:
        def __enter__(self):
            self.context = pytest.raises(cg.Error)
            self.info = self.context.__enter__()
            return self.info

        def __exit__(self, *exc):
            suppressed = self.context.__exit__(*exc)
            error = self.info.value
            assert error.status == status, (error.status, str(error))
            assert isinstance(error.status, cg.Status)
            assert error.message and error.message in str(error)
            if function:
                assert error.function == function and str(error).startswith(function)
            return suppressed

    return Expect()


def test_bad_configs():
    with raises(cg.Status.INVALID_ARGUMENT, "cg_crowd_create") as info:
        cg.Crowd(max_characters=0)
    assert "max_characters" in info.value.message
    with raises(cg.Status.INVALID_ARGUMENT):
        cg.Crowd(up_axis=cg.Axis.POSITIVE_Y, forward_axis=cg.Axis.NEGATIVE_Y)
    with raises(cg.Status.NON_FINITE):
        cg.Crowd(units_per_metre=float("nan"))
    config = cg.crowd_config()
    config.struct_size = 3
    with raises(cg.Status.BAD_STRUCT_SIZE) as info:
        cg.Crowd(config)
    assert "struct_size is 3" in info.value.message
    with pytest.raises(TypeError):
        cg.Crowd(no_such_field=1)
    with raises(cg.Status.INVALID_ARGUMENT, "cg_view_blender_create"):
        cg.ViewBlender(joint_count=0, key_count=2)


def test_failed_calls_change_nothing():
    def make():
        crowd = cg.Crowd(max_characters=2, max_objects=0, seed=5)
        ids = [crowd.add_character((0, 0, 0)), crowd.add_character((1, 0, 3), heading=np.pi)]
        return crowd, ids

    crowd, ids = make()
    twin, _ = make()
    states = cg.entity_states(ids, [[0, 0, 0], [1, 0, 3]])
    for c in (crowd, twin):
        c.push_frame(0.0, states)
    bad = states.copy()
    bad["position"][1, 0] = np.nan
    with raises(cg.Status.NON_FINITE, "cg_crowd_push_frame"):
        crowd.push_frame(0.1, bad)
    unknown = cg.entity_states([77], [[0, 0, 0]])
    with raises(cg.Status.NOT_FOUND):
        crowd.push_frame(0.1, unknown)
    with raises(cg.Status.INVALID_ARGUMENT):
        crowd.push_frame(-1.0, states)  # earlier than the previous frame
    with raises(cg.Status.INVALID_ARGUMENT, "cg_crowd_step"):
        crowd.step(-1.0)
    with raises(cg.Status.NON_FINITE):
        crowd.step(float("inf"))
    with raises(cg.Status.CAPACITY, "cg_crowd_add_character"):
        crowd.add_character((5, 0, 5))
    with raises(cg.Status.CAPACITY):
        crowd.add_object((5, 0, 5))
    with raises(cg.Status.NOT_FOUND):
        crowd.remove_entity(1234)
    with raises(cg.Status.NOT_FOUND):
        crowd.set_gaze_target(1234, point=(0, 0, 1))
    with raises(cg.Status.INVALID_ARGUMENT):
        crowd.set_gaze_target(ids[0], entity=ids[0])  # itself
    with raises(cg.Status.INVALID_ARGUMENT):
        crowd.set_base_pose(ids[0], np.tile([0, 0, 0, 1], (3, 1)))  # 3 joints, not 10
    with raises(cg.Status.INVALID_ARGUMENT):
        crowd.set_base_pose(ids[0], np.zeros((10, 4)))  # zero quaternions
    with raises(cg.Status.WRONG_STATE, "cg_crowd_plan"):
        crowd.plan()  # nothing recorded
    with raises(cg.Status.INVALID_ARGUMENT):
        crowd.read_joints(first=1, count=5)
    with raises(cg.Status.INVALID_ARGUMENT):
        crowd.set_character_params(ids[0], attention_fraction=2.0)
    # After all that, the crowd behaves exactly as its twin that never saw a bad call.
    for c in (crowd, twin):
        for frame in range(1, 31):
            states["position"][1, 2] = 3 - 0.05 * frame
            c.push_frame(frame / 30, states)
            c.step(1 / 30)
    assert crowd.read_joints().tobytes() == twin.read_joints().tobytes()
    assert crowd.read_gaze().tobytes() == twin.read_gaze().tobytes()


def test_raw_calls_return_statuses():
    crowd = cg.Crowd(max_characters=1)
    crowd.add_character()
    out = (cg.Quat * 5)()
    assert cg.lib.cg_crowd_read_joints(crowd.handle, 0, 1, out, 5) == cg.CG_STATUS_INVALID_ARGUMENT
    assert "out_len" in cg.last_error_message() or "5" in cg.last_error_message()
    assert cg.lib.cg_crowd_step(None, 0.1) == cg.CG_STATUS_NULL_ARGUMENT
    assert cg.lib.cg_crowd_push_frame(crowd.handle, 0.0, None, 1) == cg.CG_STATUS_NULL_ARGUMENT
    assert cg.lib.cg_crowd_push_frame(crowd.handle, 0.0, None, 0) == cg.CG_STATUS_OK
    assert cg.status_string(cg.Status.NOT_FOUND) == cg.lib.cg_status_str(4).decode()
    assert cg.status_string(12345) == "unknown status"
    # The message is per thread: a new thread has none.
    seen = []
    thread = threading.Thread(target=lambda: seen.append(cg.last_error_message()))
    thread.start()
    thread.join()
    assert seen == [""]
    assert cg.last_error_message() != ""


def test_blend_errors():
    q = cg.dualquat_from_rt((0, 0, 0, 1), (0, 0, 0))
    with raises(cg.Status.INVALID_ARGUMENT, "cg_blend_dlb"):
        cg.blend_dlb([q, q], [-1.0, 2.0])
    with raises(cg.Status.NON_FINITE):
        cg.blend_dlb([q, q], [np.nan, 1.0])
    with pytest.raises(ValueError):
        cg.blend_dlb([q, q], [1.0])  # counts differ: caught before C
    with raises(cg.Status.INVALID_ARGUMENT):
        cg.dualquat_from_rt((0, 0, 0, 0), (0, 0, 0))
    with raises(cg.Status.INVALID_ARGUMENT, "cg_dualquat_from_matrix"):
        cg.dualquat_from_matrix(np.diag([2.0, 1, 1, 1]))  # a scale
    with raises(cg.Status.INVALID_ARGUMENT):
        cg.camera_center_from_projection(
            np.zeros((3, 4)) + [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]]
        )

    blender = cg.ViewBlender(joint_count=1, key_count=2)
    character = cg.dualquat_from_rt((0, 0, 0, 1), (0, 0, 0))
    with raises(cg.Status.WRONG_STATE, "cg_view_blender_weights"):
        blender.weights(character, (0, 0, 5))  # no key camera yet
    blender.add_camera((0, 0, 1), 0)
    blender.add_camera((1, 0, 0), 1)
    blender.set_key_pose(0, [q])
    with raises(cg.Status.WRONG_STATE, "cg_view_blender_evaluate"):
        blender.evaluate(character, (0, 0, 5), 0.0)  # key 1 has no clip or pose
    blender.set_key_pose(1, [q])
    with raises(cg.Status.INVALID_ARGUMENT):
        blender.weights(character, (0, 0, 0))  # the viewer at the character's centre
    with raises(cg.Status.INVALID_ARGUMENT):
        blender.add_camera((0, 0, 0), 0)
    with raises(cg.Status.INVALID_ARGUMENT):
        blender.set_key_pose(2, [q])  # no key 2
    with pytest.raises(ValueError):
        blender.set_key_clip(0, np.zeros((3, 4)), 10.0)  # not dual quaternions
    blender.close()
    blender.close()  # twice is fine
    with pytest.raises(ValueError):
        blender.weights(character, (0, 0, 5))


def test_error_is_an_exception_with_fields():
    error = cg.Error(cg.Status.CAPACITY, "full", "cg_x")
    assert isinstance(error, Exception)
    assert (error.status, error.message, error.function, str(error)) == (
        cg.Status.CAPACITY,
        "full",
        "cg_x",
        "cg_x: full",
    )
    assert str(cg.Error(99, "")) == "unknown status"
    assert ctypes.sizeof(cg.CrowdConfig) > 0
