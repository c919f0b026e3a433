"""Dual quaternions, DLB/DIB and a view blender run through the Python binding."""

import numpy as np
import pytest

import crowdgaze as cg


def yaw(degrees):
    """Rotation about +Y, x y z w."""
    half = np.radians(degrees) / 2
    return np.array([0, np.sin(half), 0, np.cos(half)], np.float32)


def nod(degrees):
    half = np.radians(degrees) / 2
    return np.array([np.sin(half), 0, 0, np.cos(half)], np.float32)


def quat_multiply(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ],
        np.float32,
    )


def yaw_of(dual_quat):
    x, y, z, w = dual_quat[:4]
    return np.degrees(np.arctan2(2 * (x * z + w * y), 1 - 2 * (x * x + y * y)))


def test_dual_quaternion_round_trips():
    q = cg.dualquat_from_rt(yaw(90), (1, 2, 3))
    assert q.shape == (8,) and q.dtype == np.float32
    matrix = cg.dualquat_to_matrix(q)
    # Rotating +Z by 90 degrees about +Y gives +X; the translation is in the last column.
    np.testing.assert_allclose(matrix @ [0, 0, 1, 1], [2, 2, 3, 1], atol=1e-6)
    np.testing.assert_allclose(matrix[:3, 3], [1, 2, 3], atol=1e-6)
    np.testing.assert_allclose(cg.dualquat_from_matrix(matrix), q, atol=1e-6)
    # 16 floats are taken column-major, as C and OpenGL store them.
    np.testing.assert_allclose(cg.dualquat_from_matrix(matrix.T.ravel()), q, atol=1e-6)
    rotation, translation = cg.dualquat_to_rt(q)
    np.testing.assert_allclose(rotation, yaw(90), atol=1e-6)
    np.testing.assert_allclose(translation, [1, 2, 3], atol=1e-6)
    # A ctypes DualQuat is accepted as well.
    struct = cg.DualQuat.from_buffer_copy(q.tobytes())
    np.testing.assert_allclose(cg.dualquat_to_matrix(struct), matrix)


def test_dlb_and_dib_halve_a_screw_motion():
    inputs = np.stack(
        [cg.dualquat_from_rt(yaw(0), (0, 0, 0)), cg.dualquat_from_rt(yaw(80), (2, 0, 0))]
    )
    dlb = cg.blend_dlb(inputs, [0.5, 0.5])
    dib = cg.blend_dib(inputs, [0.5, 0.5])
    assert yaw_of(dlb) == pytest.approx(40, abs=1e-3)
    assert yaw_of(dib) == pytest.approx(40, abs=1e-3)
    # DIB of two is ScLERP: the translation (2, 0, 0) is perpendicular to the axis, so the
    # motion is a turn of 80 degrees about a pivot at |c| = 1 / sin 40 from the origin, and
    # half-way it is a turn of 40 about the same pivot: |t| = 2 |c| sin 20 = 1 / cos 20.
    half = cg.dualquat_to_rt(dib)[1]
    assert np.linalg.norm(half) == pytest.approx(1.0 / np.cos(np.radians(20)), rel=1e-5)
    assert half[1] == pytest.approx(0, abs=1e-6)
    pose_dlb = cg.blend_pose_dlb(inputs.reshape(2, 1, 8), [0.5, 0.5])
    np.testing.assert_allclose(pose_dlb[0], dlb, atol=1e-6)
    pose_dib, converged = cg.blend_pose_dib(inputs, [0.5, 0.5], return_converged=True)
    assert converged
    np.testing.assert_allclose(pose_dib[0], dib, atol=1e-6)


def test_dib_not_converged_is_reported():
    inputs = np.stack([cg.dualquat_from_rt(yaw(a), (a / 30, 0, 0)) for a in (0, 100, 170)])
    weights = [0.2, 0.3, 0.5]
    result, converged = cg.blend_dib(
        inputs, weights, precision=1e-9, max_iterations=1, return_converged=True
    )
    assert not converged and np.all(np.isfinite(result))
    with pytest.warns(cg.NotConvergedWarning):
        cg.blend_dib(inputs, weights, precision=1e-9, max_iterations=1)
    assert cg.blend_dib(inputs, weights, precision=1e-5, max_iterations=50, return_converged=True)[
        1
    ]


def test_camera_centre():
    centre = np.array([4.0, 1.6, 1.0])
    k = np.array([[800, 0, 320], [0, 800, 240], [0, 0, 1]], np.float64)
    p = k @ np.hstack([np.eye(3), -centre[:, None]])
    np.testing.assert_allclose(cg.camera_center_from_projection(p), centre, atol=1e-3)


JOINTS = 2  # neck, head


def key_frames(head_yaw, frames=10):
    """A one-second loop: the head turned `head_yaw` and nodding +-4 degrees."""
    clip = np.empty((frames, JOINTS, 8), np.float32)
    for f in range(frames):
        clip[f, 0] = cg.dualquat_from_rt(yaw(0), (0, 1.5, 0))
        clip[f, 1] = cg.dualquat_from_rt(
            quat_multiply(yaw(head_yaw), nod(4 * np.sin(2 * np.pi * f / frames))), (0, 0.2, 0)
        )
    return clip


def direction(degrees, distance=1.0):
    return distance * np.array([np.sin(np.radians(degrees)), 0, np.cos(np.radians(degrees))])


@pytest.mark.parametrize("method", [cg.BlendMethod.DLB, cg.BlendMethod.DIB])
def test_view_blender_follows_the_viewer(method):
    with cg.ViewBlender(joint_count=JOINTS, key_count=2, method=method) as blender:
        for key, angle in enumerate((0, 60)):
            blender.set_key_clip(key, key_frames(angle), 10.0, looping=True)
            blender.add_camera(direction(angle), key)
        # The character stands at (5, 0, 0) turned 90 degrees: its +Z faces world +X.
        character = cg.dualquat_from_rt(yaw(90), (5, 0, 0))
        to_world = cg.dualquat_to_matrix(character)

        def viewer(local_degrees, distance):
            return (to_world @ np.append(direction(local_degrees, distance), 1))[:3]

        # On a key camera, at any distance: that key alone, and its pose.
        for key, angle in enumerate((0, 60)):
            weights = blender.weights(character, viewer(angle, 7))
            np.testing.assert_array_equal(weights, np.eye(2, dtype=np.float32)[key])
            pose = blender.evaluate(character, viewer(angle, 7), 0.0)
            assert yaw_of(pose[1]) == pytest.approx(angle, abs=1e-3)
        # Half-way between the cameras: half and half, the head half-way.
        weights = blender.weights(character, viewer(30, 4))
        np.testing.assert_allclose(weights, [0.5, 0.5], atol=1e-5)
        pose = blender.evaluate(character, viewer(30, 4), 0.0)
        assert pose.shape == (JOINTS, 8)
        assert yaw_of(pose[1]) == pytest.approx(30, abs=0.01)
        np.testing.assert_allclose(cg.dualquat_to_rt(pose[1])[1], [0, 0.2, 0], atol=1e-5)
        # A quarter into the loop the head nods 4 degrees: read from the clip, blended.
        pose = blender.evaluate(character, viewer(30, 4), 0.25)
        expected = quat_multiply(yaw(30), nod(4))
        assert abs(np.dot(pose[1][:4], expected)) == pytest.approx(1, abs=1e-5)
        # Weights nearer a camera lean to its key, and always sum to 1.
        for local in (-40, 10, 20, 45, 90):
            weights = blender.weights(character, viewer(local, 3))
            assert weights.sum() == pytest.approx(1, abs=1e-6)
            assert (weights[0] > weights[1]) == (abs(local) < abs(local - 60))
        # Outputs into the caller's arrays.
        out = np.zeros((JOINTS, 8), np.float32)
        assert blender.evaluate(character, viewer(30, 4), 0.0, out=out) is out
        assert yaw_of(out[1]) == pytest.approx(30, abs=0.01)
        w = np.zeros(2, np.float32)
        assert blender.weights(character, viewer(30, 4), out=w) is w
        np.testing.assert_allclose(w, [0.5, 0.5], atol=1e-5)
        with pytest.raises(TypeError, match="out must have the dtype float32"):
            blender.weights(character, viewer(30, 4), out=np.zeros(2, np.float64))
        # A static pose for key 1.
        blender.set_key_pose(1, key_frames(-30)[0])
        pose = blender.evaluate(character, viewer(60, 2), 0.0)
        assert yaw_of(pose[1]) == pytest.approx(-30, abs=1e-3)
