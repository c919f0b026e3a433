"""Dual quaternions, DLB/DIB blending and ``crowdgaze.ViewBlender`` (the ``cg_view_blender``
handle).

Dual quaternions are float32 arrays of 8 (``real`` x y z w, then ``dual`` x y z w), poses
``(joints, 8)``; a float32 C-contiguous array goes to C without a copy.
"""

from __future__ import annotations

import warnings
from ctypes import POINTER, byref, c_float

import numpy as np

from . import _arrays as a
from . import _native as n
from ._errors import check, check_converged
from ._library import lib


class NotConvergedWarning(UserWarning):
    """DIB reached its iteration limit; the result is the best iterate."""


def _converged(status: int, function: str, return_converged: bool) -> bool:
    converged = check_converged(status, function)
    if not converged and not return_converged:
        warnings.warn(f"{function}: precision not reached", NotConvergedWarning, stacklevel=3)
    return converged


def _one_dualquat(value, name: str) -> np.ndarray:
    rows = a.float_rows(value, n.DualQuat, name)
    if len(rows) != 1:
        raise ValueError(f"{name}: expected one dual quaternion (8 floats), got {len(rows)}")
    return rows


def dualquat_from_rt(rotation, translation) -> np.ndarray:
    """The rigid transform "rotate by ``rotation`` (x y z w), then translate by
    ``translation``" as a dual quaternion (8 float32)."""
    out = np.empty(8, dtype=np.float32)
    check(
        lib.cg_dualquat_from_rt(
            byref(a.quat(rotation, "rotation")),
            byref(a.vec3(translation, "translation")),
            a.pointer(out, n.DualQuat),
        ),
        "cg_dualquat_from_rt",
    )
    return out


def dualquat_to_rt(dual_quat) -> tuple[np.ndarray, np.ndarray]:
    """``(rotation (4,), translation (3,))`` of a rigid transform."""
    q = _one_dualquat(dual_quat, "dual_quat")
    rotation, translation = n.Quat(), n.Vec3()
    check(
        lib.cg_dualquat_to_rt(a.pointer(q, n.DualQuat), byref(rotation), byref(translation)),
        "cg_dualquat_to_rt",
    )
    return np.array(tuple(rotation), np.float32), np.array(tuple(translation), np.float32)


def dualquat_from_matrix(matrix) -> np.ndarray:
    """A dual quaternion from a rigid 4x4 matrix: a ``(4, 4)`` array indexed
    ``[row, column]`` for column vectors (translation in ``matrix[:3, 3]``), or 16 floats
    already column-major as C takes them (OpenGL, ``osg::Matrixf::ptr()``)."""
    m = np.asarray(matrix, dtype=np.float32)
    if m.shape == (4, 4):
        m = m.T
    m = np.ascontiguousarray(m.reshape(16))
    out = np.empty(8, dtype=np.float32)
    check(
        lib.cg_dualquat_from_matrix(a.pointer(m, c_float), a.pointer(out, n.DualQuat)),
        "cg_dualquat_from_matrix",
    )
    return out


def dualquat_to_matrix(dual_quat) -> np.ndarray:
    """The ``(4, 4)`` matrix ``[row, column]`` for column vectors (translation in
    ``[:3, 3]``); ``.T.ravel()`` gives C's column-major 16 floats."""
    q = _one_dualquat(dual_quat, "dual_quat")
    out = np.empty(16, dtype=np.float32)
    check(
        lib.cg_dualquat_to_matrix(a.pointer(q, n.DualQuat), a.pointer(out, c_float)),
        "cg_dualquat_to_matrix",
    )
    return out.reshape(4, 4).T.copy()


def _inputs_and_weights(inputs, weights):
    q = a.float_rows(inputs, n.DualQuat, "inputs")
    w = a.float_values(weights, "weights")
    if len(q) != w.size:
        raise ValueError(f"{len(q)} inputs but {w.size} weights")
    return q, w


def blend_dlb(inputs, weights) -> np.ndarray:
    """DLB of ``inputs`` (``(n, 8)``) with ``weights`` (``n``): one dual quaternion."""
    q, w = _inputs_and_weights(inputs, weights)
    out = np.empty(8, dtype=np.float32)
    check(
        lib.cg_blend_dlb(
            a.pointer(q, n.DualQuat), a.pointer(w, c_float), len(q), a.pointer(out, n.DualQuat)
        ),
        "cg_blend_dlb",
    )
    return out


def blend_dib(inputs, weights, precision=1e-6, max_iterations=16, *, return_converged=False):
    """DIB of ``inputs`` with ``weights``. Returns the dual quaternion, or with
    ``return_converged=True`` a tuple ``(dual_quat, converged)``; if the precision is not
    reached, the best iterate (with a ``NotConvergedWarning`` unless ``return_converged``)."""
    q, w = _inputs_and_weights(inputs, weights)
    out = np.empty(8, dtype=np.float32)
    status = lib.cg_blend_dib(
        a.pointer(q, n.DualQuat),
        a.pointer(w, c_float),
        len(q),
        precision,
        max_iterations,
        a.pointer(out, n.DualQuat),
    )
    converged = _converged(status, "cg_blend_dib", return_converged)
    return (out, converged) if return_converged else out


def _keys(keys, weights, joint_count):
    w = a.float_values(weights, "weights")
    k = a.float_rows(keys, n.DualQuat, "keys")
    if joint_count is None:
        if len(k) % max(w.size, 1) != 0:
            raise ValueError(f"{len(k)} key transforms do not split into {w.size} keys")
        joint_count = len(k) // max(w.size, 1)
    if len(k) != w.size * joint_count:
        raise ValueError(f"expected {w.size} x {joint_count} key transforms, got {len(k)}")
    return k, w, joint_count


def blend_pose_dlb(keys, weights, out=None) -> np.ndarray:
    """DLB of whole poses: ``keys`` ``(key_count, joints, 8)`` (or key-major
    ``(key_count * joints, 8)``), ``weights`` ``(key_count,)``; returns ``(joints, 8)``."""
    k, w, joints = _keys(keys, weights, None)
    target = a.FloatOut(out, joints, 8, "out")
    check(
        lib.cg_blend_pose_dlb(
            a.pointer(k, n.DualQuat),
            a.pointer(w, c_float),
            w.size,
            joints,
            a.pointer(target.buffer, n.DualQuat),
        ),
        "cg_blend_pose_dlb",
    )
    return target.result()


def blend_pose_dib(
    keys, weights, precision=1e-6, max_iterations=16, out=None, *, return_converged=False
):
    """DIB of whole poses, laid out as ``blend_pose_dlb``."""
    k, w, joints = _keys(keys, weights, None)
    target = a.FloatOut(out, joints, 8, "out")
    status = lib.cg_blend_pose_dib(
        a.pointer(k, n.DualQuat),
        a.pointer(w, c_float),
        w.size,
        joints,
        precision,
        max_iterations,
        a.pointer(target.buffer, n.DualQuat),
    )
    converged = _converged(status, "cg_blend_pose_dib", return_converged)
    return (target.result(), converged) if return_converged else target.result()


def camera_center_from_projection(projection) -> np.ndarray:
    """The centre ``C = -R^T t`` of a camera ``P = K[R|t]`` given as a ``(3, 4)`` array."""
    p = np.ascontiguousarray(np.asarray(projection, dtype=np.float32).reshape(12))
    out = n.Vec3()
    check(
        lib.cg_camera_center_from_projection(a.pointer(p, c_float), byref(out)),
        "cg_camera_center_from_projection",
    )
    return np.array(tuple(out), np.float32)


def view_blender_config(**fields) -> n.ViewBlenderConfig:
    """A ``ViewBlenderConfig`` with the library's defaults, then ``fields``."""
    config = n.ViewBlenderConfig()
    check(lib.cg_view_blender_config_init(byref(config)), "cg_view_blender_config_init")
    known = {name for name, _ in n.ViewBlenderConfig._fields_}
    for name, value in fields.items():
        if name not in known:
            raise TypeError(f"cg_view_blender_config has no field {name!r}")
        setattr(config, name, int(value) if name in ("distance", "method") else value)
    return config


class ViewBlender:
    """View-adaptive blending of key animations for a character.

    ``ViewBlender(joint_count=5, key_count=3, method=BlendMethod.DIB)`` or
    ``ViewBlender(config)``. Close with ``close()`` or a ``with`` block.
    """

    def __init__(self, config: n.ViewBlenderConfig | None = None, **fields):
        if config is None:
            config = view_blender_config(**fields)
        handle = POINTER(n.ViewBlenderHandle)()
        check(lib.cg_view_blender_create(byref(config), byref(handle)), "cg_view_blender_create")
        self._handle = handle
        self.joint_count = config.joint_count
        self.key_count = config.key_count

    @property
    def handle(self):
        """The ``cg_view_blender*`` (a ctypes pointer)."""
        if not self._handle:
            raise ValueError("view blender is closed")
        return self._handle

    def close(self) -> None:
        handle, self._handle = getattr(self, "_handle", None), POINTER(n.ViewBlenderHandle)()
        if handle:
            lib.cg_view_blender_destroy(handle)

    def __enter__(self) -> ViewBlender:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        self.close()

    def set_key_clip(
        self, key: int, frames, frames_per_second: float, looping: bool = True
    ) -> None:
        """Key ``key`` plays ``frames``: ``(frame_count, joints, 8)`` (or frame-major
        ``(frame_count * joints, 8)``) local joint transforms."""
        f = a.float_rows(frames, n.DualQuat, "frames")
        if self.joint_count == 0 or len(f) % self.joint_count != 0:
            raise ValueError(
                f"{len(f)} transforms are not whole frames of {self.joint_count} joints"
            )
        check(
            lib.cg_view_blender_set_key_clip(
                self.handle,
                key,
                a.pointer(f, n.DualQuat),
                len(f) // self.joint_count,
                frames_per_second,
                looping,
            ),
            "cg_view_blender_set_key_clip",
        )

    def set_key_pose(self, key: int, pose) -> None:
        """Key ``key`` is the static pose ``pose`` (``(joints, 8)``)."""
        p = a.float_rows(pose, n.DualQuat, "pose")
        check(
            lib.cg_view_blender_set_key_pose(self.handle, key, a.pointer(p, n.DualQuat), len(p)),
            "cg_view_blender_set_key_pose",
        )

    def add_camera(self, direction, key: int) -> None:
        """A key camera: ``direction`` from the character's centre in its own frame."""
        check(
            lib.cg_view_blender_add_camera(self.handle, a.vec3(direction, "direction"), key),
            "cg_view_blender_add_camera",
        )

    def weights(self, character, viewer, out=None) -> np.ndarray:
        """The key weights (``(key_count,)`` float32) for a viewer at ``viewer`` looking at
        the character placed by the dual quaternion ``character``."""
        c = _one_dualquat(character, "character")
        target = a.FloatOut(out, self.key_count, 1, "out", shape=(self.key_count,))
        check(
            lib.cg_view_blender_weights(
                self.handle,
                a.pointer(c, n.DualQuat),
                byref(a.vec3(viewer, "viewer")),
                a.pointer(target.buffer, c_float),
                self.key_count,
            ),
            "cg_view_blender_weights",
        )
        return target.result()

    def evaluate(self, character, viewer, t: float, out=None, *, return_converged=False):
        """The blended pose (``(joints, 8)``) at clip time ``t``; with
        ``return_converged=True`` a tuple ``(pose, converged)``."""
        c = _one_dualquat(character, "character")
        target = a.FloatOut(out, self.joint_count, 8, "out")
        status = lib.cg_view_blender_evaluate(
            self.handle,
            a.pointer(c, n.DualQuat),
            byref(a.vec3(viewer, "viewer")),
            t,
            a.pointer(target.buffer, n.DualQuat),
            self.joint_count,
        )
        converged = _converged(status, "cg_view_blender_evaluate", return_converged)
        return (target.result(), converged) if return_converged else target.result()
