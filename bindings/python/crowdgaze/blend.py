"""Dual quaternions, DLB/DIB blending and ``crowdgaze.ViewBlender`` (the ``cg_view_blender``
handle).

Dual quaternions are float32 arrays of 8 (``real`` x y z w, then ``dual`` x y z w), poses
``(joints, 8)``; a float32 C-contiguous array goes to C without a copy. Arguments are
converted and checked as in ``crowdgaze.crowd`` (errors name the argument), and a
``ViewBlender`` guards its handle as a ``Crowd`` does (``crowdgaze._owner``).
"""

from __future__ import annotations

import warnings
from typing import Any
from ctypes import POINTER, byref, c_float, sizeof

import numpy as np
from numpy.typing import NDArray

from . import _exceptions as e
from . import _arrays as a
from . import _checks as c
from . import _native as n
from ._errors import check, check_converged
from ._library import lib
from ._owner import HandleOwner


class NotConvergedWarning(UserWarning):
    """DIB reached its iteration limit; the result is the best iterate."""


def _converged(status: int, function: str, return_converged: bool) -> bool:
    converged = check_converged(status, function)
    if not converged and not return_converged:
        warnings.warn(f"{function}: precision not reached", NotConvergedWarning, stacklevel=3)
    return converged


def _one_dualquat(value: a.Numbers, where: str, name: str) -> NDArray[Any]:
    rows = a.float_rows(value, n.DualQuat, where, name)
    if len(rows) != 1:
        raise e.value_error(
            f"{where}: {name} must be one dual quaternion (8 numbers), got {len(rows)}"
        )
    return rows


def dualquat_from_rt(rotation: a.Numbers, translation: a.Numbers) -> NDArray[Any]:
    """The rigid transform "rotate by ``rotation`` (x y z w), then translate by
    ``translation``" as a dual quaternion (8 float32)."""
    where = "dualquat_from_rt"
    rotation = a.quat(rotation, where, "rotation")
    translation = a.vec3(translation, where, "translation")
    out = np.empty(8, dtype=np.float32)
    check(
        lib.cg_dualquat_from_rt(byref(rotation), byref(translation), a.pointer(out, n.DualQuat)),
        "cg_dualquat_from_rt",
    )
    return out


def dualquat_to_rt(dual_quat: a.Numbers) -> tuple[NDArray[Any], NDArray[Any]]:
    """``(rotation (4,), translation (3,))`` of a rigid transform."""
    q = _one_dualquat(dual_quat, "dualquat_to_rt", "dual_quat")
    rotation, translation = n.Quat(), n.Vec3()
    check(
        lib.cg_dualquat_to_rt(a.pointer(q, n.DualQuat), byref(rotation), byref(translation)),
        "cg_dualquat_to_rt",
    )
    return np.array(tuple(rotation), np.float32), np.array(tuple(translation), np.float32)


def dualquat_from_matrix(matrix: a.Numbers) -> NDArray[Any]:
    """A dual quaternion from a rigid 4x4 matrix: a ``(4, 4)`` array indexed
    ``[row, column]`` for column vectors (translation in ``matrix[:3, 3]``), or 16 floats
    already column-major as C takes them (OpenGL, ``osg::Matrixf::ptr()``)."""
    where = "dualquat_from_matrix"
    m = a.fixed_floats(matrix, 16, where, "matrix", shapes=[(4, 4), (16,)])
    if m.shape == (4, 4):
        m = m.T
    m = np.ascontiguousarray(m.reshape(16))
    out = np.empty(8, dtype=np.float32)
    check(
        lib.cg_dualquat_from_matrix(a.pointer(m, c_float), a.pointer(out, n.DualQuat)),
        "cg_dualquat_from_matrix",
    )
    return out


def dualquat_to_matrix(dual_quat: a.Numbers) -> NDArray[Any]:
    """The ``(4, 4)`` matrix ``[row, column]`` for column vectors (translation in
    ``[:3, 3]``); ``.T.ravel()`` gives C's column-major 16 floats."""
    q = _one_dualquat(dual_quat, "dualquat_to_matrix", "dual_quat")
    out = np.empty(16, dtype=np.float32)
    check(
        lib.cg_dualquat_to_matrix(a.pointer(q, n.DualQuat), a.pointer(out, c_float)),
        "cg_dualquat_to_matrix",
    )
    return out.reshape(4, 4).T.copy()


def _inputs_and_weights(inputs: a.Numbers, weights: a.Numbers, where: str) -> tuple[NDArray[Any], NDArray[Any]]:
    q = a.float_rows(inputs, n.DualQuat, where, "inputs")
    w = a.float_values(weights, where, "weights")
    if len(q) != w.size:
        raise e.value_error(
            f"{where}: inputs holds {len(q)} dual quaternions but weights {w.size} weights"
        )
    return q, w


def _dib_settings(precision: Any, max_iterations: Any, where: str) -> tuple[float, int]:
    return c.real(precision, where, "precision"), c.integer(
        max_iterations, where, "max_iterations"
    )


def blend_dlb(inputs: a.Numbers, weights: a.Numbers) -> NDArray[Any]:
    """DLB of ``inputs`` (``(n, 8)``) with ``weights`` (``n``): one dual quaternion."""
    q, w = _inputs_and_weights(inputs, weights, "blend_dlb")
    out = np.empty(8, dtype=np.float32)
    check(
        lib.cg_blend_dlb(
            a.pointer(q, n.DualQuat), a.pointer(w, c_float), len(q), a.pointer(out, n.DualQuat)
        ),
        "cg_blend_dlb",
    )
    return out


def blend_dib(
    inputs: a.Numbers,
    weights: a.Numbers,
    precision: float = 1e-6,
    max_iterations: int = 16,
    *,
    return_converged: bool = False,
) -> NDArray[Any] | tuple[NDArray[Any], bool]:
    """DIB of ``inputs`` with ``weights``. Returns the dual quaternion, or with
    ``return_converged=True`` a tuple ``(dual_quat, converged)``; if the precision is not
    reached, the best iterate (with a ``NotConvergedWarning`` unless ``return_converged``)."""
    where = "blend_dib"
    q, w = _inputs_and_weights(inputs, weights, where)
    precision, max_iterations = _dib_settings(precision, max_iterations, where)
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


def _keys(keys: a.Numbers, weights: a.Numbers, where: str) -> tuple[NDArray[Any], NDArray[Any], int]:
    w = a.float_values(weights, where, "weights")
    k = a.float_rows(keys, n.DualQuat, where, "keys")
    if len(k) % max(w.size, 1) != 0:
        raise e.value_error(
            f"{where}: keys holds {len(k)} transforms, not whole poses of the {w.size} keys "
            f"weights has"
        )
    return k, w, len(k) // max(w.size, 1)


def blend_pose_dlb(keys: a.Numbers, weights: a.Numbers, out: a.Out = None) -> NDArray[Any]:
    """DLB of whole poses: ``keys`` ``(key_count, joints, 8)`` (or key-major
    ``(key_count * joints, 8)``), ``weights`` ``(key_count,)``; returns ``(joints, 8)``, or
    ``out`` (exactly that: float32, C-contiguous, writeable) written in place."""
    where = "blend_pose_dlb"
    k, w, joints = _keys(keys, weights, where)
    out = a.output(out, a.FLOAT32, (joints, 8), where)
    check(
        lib.cg_blend_pose_dlb(
            a.pointer(k, n.DualQuat),
            a.pointer(w, c_float),
            w.size,
            joints,
            a.pointer(out, n.DualQuat),
        ),
        "cg_blend_pose_dlb",
    )
    return out


def blend_pose_dib(
    keys: a.Numbers,
    weights: a.Numbers,
    precision: float = 1e-6,
    max_iterations: int = 16,
    out: a.Out = None,
    *,
    return_converged: bool = False,
) -> NDArray[Any] | tuple[NDArray[Any], bool]:
    """DIB of whole poses, laid out as ``blend_pose_dlb``."""
    where = "blend_pose_dib"
    k, w, joints = _keys(keys, weights, where)
    precision, max_iterations = _dib_settings(precision, max_iterations, where)
    out = a.output(out, a.FLOAT32, (joints, 8), where)
    status = lib.cg_blend_pose_dib(
        a.pointer(k, n.DualQuat),
        a.pointer(w, c_float),
        w.size,
        joints,
        precision,
        max_iterations,
        a.pointer(out, n.DualQuat),
    )
    converged = _converged(status, "cg_blend_pose_dib", return_converged)
    return (out, converged) if return_converged else out


def camera_center_from_projection(projection: a.Numbers) -> NDArray[Any]:
    """The centre ``C = -R^T t`` of a camera ``P = K[R|t]`` given as a ``(3, 4)`` array (or
    12 numbers, row-major)."""
    where = "camera_center_from_projection"
    p = a.fixed_floats(projection, 12, where, "projection", shapes=[(3, 4), (12,)])
    p = np.ascontiguousarray(p.reshape(12))
    out = n.Vec3()
    check(
        lib.cg_camera_center_from_projection(a.pointer(p, c_float), byref(out)),
        "cg_camera_center_from_projection",
    )
    return np.array(tuple(out), np.float32)


def _blender_config(fields: dict[str, Any], where: str) -> n.ViewBlenderConfig:
    converted = a.struct_fields(n.ViewBlenderConfig, fields, where)
    config = n.ViewBlenderConfig(struct_size=sizeof(n.ViewBlenderConfig))
    check(lib.cg_view_blender_config_init(byref(config)), "cg_view_blender_config_init")
    return a.fill(config, converted)


def view_blender_config(**fields: Any) -> n.ViewBlenderConfig:
    """A ``ViewBlenderConfig`` with the library's defaults, then ``fields``."""
    return _blender_config(fields, "view_blender_config")


class ViewBlender(HandleOwner):
    """View-adaptive blending of key animations for a character.

    ``ViewBlender(joint_count=5, key_count=3, method=BlendMethod.DIB)`` or
    ``ViewBlender(config)`` (with fields too, they change a copy of it). Close with
    ``close()`` or a ``with`` block. ``weights`` and ``evaluate`` may run on several threads
    at once; the ``set``/``add`` calls take turns with every other call, and ``close()``
    from another thread waits for the calls in flight. A blender cannot be copied or
    pickled, and ``__init__`` runs once (see ``crowdgaze._owner``).
    """

    _kind = "view blender"
    _destroy: Any = lib.cg_view_blender_destroy
    _joint_count = 0
    _key_count = 0

    def __init__(self, config: n.ViewBlenderConfig | None = None, **fields: Any):
        where = "ViewBlender"
        self._refuse_reinit(where)
        if config is None:
            config = _blender_config(fields, where)
        else:
            c.instance(config, n.ViewBlenderConfig, where, "config")
            converted = a.struct_fields(n.ViewBlenderConfig, fields, where)
            config = a.fill(n.ViewBlenderConfig.from_buffer_copy(config), converted)
        handle = POINTER(n.ViewBlenderHandle)()
        check(lib.cg_view_blender_create(byref(config), byref(handle)), "cg_view_blender_create")
        self._joint_count = config.joint_count
        self._key_count = config.key_count
        self._adopt(handle, where)

    def _describe(self) -> str:
        return f"{self._joint_count} joints, {self._key_count} keys"

    @property
    def joint_count(self) -> int:
        """Joints per pose (from the config)."""
        return self._joint_count

    @property
    def key_count(self) -> int:
        """Key animations (from the config)."""
        return self._key_count

    def set_key_clip(
        self, key: int, frames: a.Numbers, frames_per_second: float, looping: bool = True
    ) -> None:
        """Key ``key`` plays ``frames``: ``(frame_count, joints, 8)`` (or frame-major
        ``(frame_count * joints, 8)``) local joint transforms."""
        where = "ViewBlender.set_key_clip"
        key = c.integer(key, where, "key")
        f = a.float_rows(frames, n.DualQuat, where, "frames")
        frames_per_second = c.real(frames_per_second, where, "frames_per_second")
        looping = c.flag(looping, where, "looping")
        if self._joint_count == 0 or len(f) % self._joint_count != 0:
            raise e.value_error(
                f"{where}: frames holds {len(f)} transforms, not whole frames of "
                f"{self._joint_count} joints"
            )
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_view_blender_set_key_clip(
                    handle,
                    key,
                    a.pointer(f, n.DualQuat),
                    len(f) // self._joint_count,
                    frames_per_second,
                    looping,
                ),
                "cg_view_blender_set_key_clip",
            )

    def set_key_pose(self, key: int, pose: a.Numbers) -> None:
        """Key ``key`` is the static pose ``pose`` (``(joints, 8)``)."""
        where = "ViewBlender.set_key_pose"
        key = c.integer(key, where, "key")
        p = a.float_rows(pose, n.DualQuat, where, "pose")
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_view_blender_set_key_pose(handle, key, a.pointer(p, n.DualQuat), len(p)),
                "cg_view_blender_set_key_pose",
            )

    def add_camera(self, direction: a.Numbers, key: int) -> None:
        """A key camera: ``direction`` from the character's centre in its own frame."""
        where = "ViewBlender.add_camera"
        direction = a.vec3(direction, where, "direction")
        key = c.integer(key, where, "key")
        with self._call(where, exclusive=True) as handle:
            check(
                lib.cg_view_blender_add_camera(handle, direction, key),
                "cg_view_blender_add_camera",
            )

    def weights(self, character: a.Numbers, viewer: a.Numbers, out: a.Out = None) -> NDArray[Any]:
        """The key weights (``(key_count,)`` float32) for a viewer at ``viewer`` looking at
        the character placed by the dual quaternion ``character``; or ``out`` (exactly
        that) written in place."""
        where = "ViewBlender.weights"
        q = _one_dualquat(character, where, "character")
        viewer = a.vec3(viewer, where, "viewer")
        out = a.output(out, a.FLOAT32, (self._key_count,), where)
        with self._call(where) as handle:
            check(
                lib.cg_view_blender_weights(
                    handle,
                    a.pointer(q, n.DualQuat),
                    byref(viewer),
                    a.pointer(out, c_float),
                    self._key_count,
                ),
                "cg_view_blender_weights",
            )
        return out

    def evaluate(
        self,
        character: a.Numbers,
        viewer: a.Numbers,
        t: float,
        out: a.Out = None,
        *,
        return_converged: bool = False,
    ) -> NDArray[Any] | tuple[NDArray[Any], bool]:
        """The blended pose (``(joints, 8)``) at clip time ``t``, or ``out`` (exactly that)
        written in place; with ``return_converged=True`` a tuple ``(pose, converged)``."""
        where = "ViewBlender.evaluate"
        q = _one_dualquat(character, where, "character")
        viewer = a.vec3(viewer, where, "viewer")
        t = c.real(t, where, "t", single=False)
        out = a.output(out, a.FLOAT32, (self._joint_count, 8), where)
        with self._call(where) as handle:
            status = lib.cg_view_blender_evaluate(
                handle,
                a.pointer(q, n.DualQuat),
                byref(viewer),
                t,
                a.pointer(out, n.DualQuat),
                self._joint_count,
            )
        converged = _converged(status, "cg_view_blender_evaluate", return_converged)
        return (out, converged) if return_converged else out
