"""Hostile calls: wrong types, out-of-range integers, foreign buffers, read-only and wrongly
typed outputs, copies, re-initialisation, and closing a crowd or blender under a call.

Every attempt runs in a child Python process, so a crash (a double free, a write into
read-only memory, a handle freed under a running call) fails a test instead of killing
pytest. Cheap attempts are batched, many to a child, each in its own try/except printing one
JSON line (label, outcome, message); the parent checks every line: the exception type (or
``Error:<STATUS>`` for a refusal by the C library) and that the message names the argument.
Crash-prone attempts each get a child of their own.
"""

from __future__ import annotations

import ctypes
import json
import os
import subprocess
import sys
import textwrap

import pytest
from conftest import PACKAGE_ROOT

import crowdgaze as cg

TYPE = "TypeError"
VALUE = "ValueError"
OVERFLOW = "OverflowError"
NON_FINITE = "Error:NON_FINITE"

PRELUDE = textwrap.dedent(
    """
    import array, copy, ctypes, gc, json, math, mmap, os, pickle, sys, tempfile, threading
    import time
    from decimal import Decimal

    import numpy as np

    import crowdgaze as cg

    nan, inf = float("nan"), float("inf")


    def outcome(error):
        # The library's refusals by status; the binding's own (function None, raised before
        # any C call) by the built-in exception they also are.
        if isinstance(error, cg.Error) and error.function is not None:
            return "Error:" + getattr(error.status, "name", str(error.status))
        for builtin in (TypeError, OverflowError, ValueError, RuntimeError):
            if isinstance(error, builtin):
                return builtin.__name__
        return type(error).__name__


    def attempt(label, call):
        try:
            call()
        except Exception as error:
            print(json.dumps([label, outcome(error), str(error)]), flush=True)
        else:
            print(json.dumps([label, "ok", ""]), flush=True)


    def expect_equal(actual, expected):
        if not np.allclose(np.asarray(actual, np.float64), np.asarray(expected, np.float64)):
            raise AssertionError(f"{actual!r} != {expected!r}")


    def records_with(field, dtype, value):
        # Entity states (without struct_size) whose field `field` has the dtype `dtype`.
        base = cg.ENTITY_STATE_DTYPE
        fields = [(n, dtype if n == field else base.fields[n][0]) for n in base.names[1:]]
        records = np.zeros(1, fields)
        records[field] = value
        return records


    def make_out(kind, shape, dtype):
        dtype = np.dtype(dtype)
        size = int(np.prod(shape))
        if kind == "readonly":
            out = np.zeros(shape, dtype)
            out.flags.writeable = False
            return out
        if kind in ("int32", "int64", "bool", "float64", "float16", "uint8"):
            return np.zeros(shape, kind)
        if kind == "bigendian":
            return np.zeros(shape, dtype.newbyteorder(">"))
        if kind == "other_records":
            return np.zeros(shape, cg.CONSTRAINT_DTYPE)
        if kind == "reordered_records":
            names = list(dtype.names)[::-1]
            return np.zeros(shape, np.dtype([(n, dtype.fields[n][0]) for n in names], align=True))
        if kind == "strided":
            return np.zeros((shape[0] * 2,) + tuple(shape[1:]), dtype)[::2]
        if kind == "transposed":
            return np.zeros(tuple(shape)[::-1], dtype).T
        if kind == "short":
            return np.zeros((shape[0] - 1,) + tuple(shape[1:]), dtype)
        if kind == "long":
            return np.zeros((shape[0] + 1,) + tuple(shape[1:]), dtype)
        if kind == "flat":
            return np.zeros(size, dtype)
        if kind == "column":
            return np.zeros(tuple(shape) + (1,), dtype)
        if kind == "list":
            return [0.0] * size
        if kind == "bytes":
            return bytes(size * dtype.itemsize)
        if kind == "bytearray":
            return bytearray(size * dtype.itemsize)
        if kind == "memoryview":
            return memoryview(bytearray(size * dtype.itemsize))
        if kind == "ctypes":
            return (ctypes.c_float * (size * dtype.itemsize // 4))()
        raise AssertionError(kind)
    """
)

# The objects the batched attempts use (created in each batch child).
SETUP = textwrap.dedent(
    """
    crowd = cg.Crowd(max_characters=8, max_objects=2, seed=1, max_recorded_states=100)
    ids = [crowd.add_character((2.0 * k, 0, 0)) for k in range(3)]
    lamp = crowd.add_object((0, 0, 3), look_at_height=1.5)
    q = np.tile(np.float32([0, 0, 0, 1]), (10, 1))
    states = cg.entity_states(ids, [[0, 0, 0], [2, 0, 0], [4, 0, 0]])
    crowd.push_frame(0.0, states)
    crowd.step(1 / 30)
    blender = cg.ViewBlender(joint_count=1, key_count=2)
    dq = cg.dualquat_from_rt((0, 0, 0, 1), (0, 0, 0))
    IDENTITY_DQ = [0, 0, 0, 1, 0, 0, 0, 0]
    for key, direction in enumerate([(0, 0, 1), (1, 0, 0)]):
        blender.set_key_pose(key, [dq])
        blender.add_camera(direction, key)
    """
)


def run_child(code: str, timeout: float = 120) -> subprocess.CompletedProcess:
    """Runs ``code`` in a new Python with this package and this library."""
    env = dict(os.environ)
    env["CROWDGAZE_LIBRARY"] = cg.library_path
    paths = [str(PACKAGE_ROOT)] + [p for p in sys.path if p and os.path.isdir(p)]
    if env.get("PYTHONPATH"):
        paths.append(env["PYTHONPATH"])
    env["PYTHONPATH"] = os.pathsep.join(paths)
    return subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=timeout
    )


def describe_child(result: subprocess.CompletedProcess) -> str:
    return (
        f"exit status {result.returncode}\nstdout (tail):\n{result.stdout[-3000:]}\n"
        f"stderr (tail):\n{result.stderr[-3000:]}"
    )


class Batch:
    """Attempts run in one child: each a Python expression, the outcomes it may have and
    the words its message must contain."""

    def __init__(self):
        self.cases: dict[str, tuple[str, tuple[str, ...], tuple[str, ...]]] = {}

    def add(self, label: str, expression: str | None, outcomes, names=()):
        """An attempt; with ``expression`` None, one the epilogue of ``run`` makes."""
        assert label not in self.cases, label
        outcomes = (outcomes,) if isinstance(outcomes, str) else tuple(outcomes)
        names = (names,) if isinstance(names, str) else tuple(names)
        self.cases[label] = (expression, outcomes, names)

    def run(self, setup: str = SETUP, epilogue: str = "") -> None:
        lines = [PRELUDE, setup]
        for label, (expression, _, _) in self.cases.items():
            if expression is not None:
                lines.append(f"attempt({label!r}, lambda: {expression})")
        lines.append(epilogue)
        result = run_child("\n".join(lines))
        assert result.returncode == 0, describe_child(result)
        seen = {}
        for line in result.stdout.splitlines():
            label, kind, message = json.loads(line)
            seen[label] = (kind, message)
        failures = []
        for label, (expression, outcomes, names) in self.cases.items():
            if label not in seen:
                failures.append(f"{label}: no outcome printed ({expression})")
                continue
            kind, message = seen[label]
            if kind not in outcomes:
                failures.append(f"{label}: {kind} {message!r}, expected {outcomes}")
            elif kind != "ok" and not all(name in message for name in names):
                failures.append(f"{label}: {kind} {message!r} does not name {names}")
        assert not failures, f"{len(failures)} of {len(self.cases)} failed:\n" + "\n".join(
            failures[:40]
        )


def run_alone(code: str, timeout: float = 120) -> dict:
    """Runs one crash-prone attempt in its own child; it prints one JSON object last."""
    result = run_child(PRELUDE + "\n" + textwrap.dedent(code), timeout)
    assert result.returncode == 0, describe_child(result)
    return json.loads(result.stdout.strip().splitlines()[-1])


# --- integers ------------------------------------------------------------------------------

#: Bad values for a uint32 argument and the exception each must raise.
BAD_UINT32 = [
    ("2**32", OVERFLOW),
    ("2**32 + 5", OVERFLOW),
    ("-1", OVERFLOW),
    ("2**64", OVERFLOW),
    ("10**30", OVERFLOW),
    ("-2**63", OVERFLOW),
    ("True", TYPE),
    ("np.True_", TYPE),
    ("1.5", TYPE),
    ("1.0", TYPE),
    ("np.float64(2.0)", TYPE),
    ("'3'", TYPE),
    ("b'1'", TYPE),
    ("[1]", TYPE),
    ("None", TYPE),
    ("Decimal(1)", TYPE),
]
BAD_UINT64 = [("2**64", OVERFLOW), ("-1", OVERFLOW), ("10**30", OVERFLOW)] + [
    (v, t) for v, t in BAD_UINT32 if t == TYPE
]
#: Values for which None is meaningful (a default) are left out by the cases below.
NOT_NONE = [(v, t) for v, t in BAD_UINT32 if v != "None"]

#: Integer arguments of the package's functions: label -> (expression, argument name, bad).
INTEGER_ARGUMENTS = {
    "remove_entity.entity": ("crowd.remove_entity({v})", "entity", BAD_UINT32),
    "character_params.character": ("crowd.character_params({v})", "character", BAD_UINT32),
    "set_character_params.character": (
        "crowd.set_character_params({v}, attention_fraction=0.5)",
        "character",
        BAD_UINT32,
    ),
    "set_attention_period.character": (
        "crowd.set_attention_period({v}, 2)",
        "character",
        BAD_UINT32,
    ),
    "set_attention_period.period": (
        "crowd.set_attention_period(ids[0], {v})",
        "period",
        BAD_UINT32,
    ),
    "set_impact.entity": ("crowd.set_impact({v}, 1.0)", "entity", BAD_UINT32),
    "step_range.first": ("crowd.step_range({v}, 1)", "first", BAD_UINT32),
    "step_range.count": ("crowd.step_range(0, {v})", "count", BAD_UINT32),
    "joint_total.first": ("crowd.joint_total({v})", "first", BAD_UINT32),
    "joint_total.count": ("crowd.joint_total(0, {v})", "count", NOT_NONE),
    "read_joints.first": ("crowd.read_joints({v})", "first", BAD_UINT32),
    "read_joints.count": ("crowd.read_joints(0, {v})", "count", NOT_NONE),
    "read_joint_deltas.first": ("crowd.read_joint_deltas({v})", "first", BAD_UINT32),
    "read_joint_deltas.count": ("crowd.read_joint_deltas(0, {v})", "count", NOT_NONE),
    "read_eyes.first": ("crowd.read_eyes({v})", "first", BAD_UINT32),
    "read_eyes.count": ("crowd.read_eyes(0, {v})", "count", NOT_NONE),
    "read_eyelids.first": ("crowd.read_eyelids({v})", "first", BAD_UINT32),
    "read_eyelids.count": ("crowd.read_eyelids(0, {v})", "count", NOT_NONE),
    "set_base_pose.character": ("crowd.set_base_pose({v}, q)", "character", BAD_UINT32),
    "set_gaze_target.character": (
        "crowd.set_gaze_target({v}, point=(0, 1, 1))",
        "character",
        BAD_UINT32,
    ),
    "set_gaze_target.entity": ("crowd.set_gaze_target(ids[0], entity={v})", "entity", NOT_NONE),
    "set_gaze_target.priority": (
        "crowd.set_gaze_target(ids[0], point=(0, 1, 1), priority={v})",
        "priority",
        NOT_NONE,
    ),
    "clear_gaze_target.character": ("crowd.clear_gaze_target({v})", "character", BAD_UINT32),
    "score.character": ("crowd.score({v}, lamp)", "character", BAD_UINT32),
    "score.entity": ("crowd.score(ids[0], {v})", "entity", BAD_UINT32),
    "read_constraints.character": ("crowd.read_constraints({v})", "character", BAD_UINT32),
    "remove_conversation.group": ("crowd.remove_conversation({v})", "group", BAD_UINT32),
    "conversation_of.character": ("crowd.conversation_of({v})", "character", BAD_UINT32),
    "add_character.attention_model": (
        "crowd.add_character((0, 0, 0), attention_model={v})",
        "attention_model",
        BAD_UINT32,
    ),
    "set_character_params.attention_model": (
        "crowd.set_character_params(ids[0], attention_model={v})",
        "attention_model",
        BAD_UINT32,
    ),
    "chain_desc_human.up_axis": ("cg.chain_desc_human({v}, 4)", "up_axis", BAD_UINT32),
    "chain_desc_human.forward_axis": ("cg.chain_desc_human(2, {v})", "forward_axis", BAD_UINT32),
    "entity_states.flags": ("cg.entity_states([0], flags={v})", "flags", BAD_UINT32),
    "status_string.status": ("cg.status_string({v})", "status", BAD_UINT32),
    "gaze_target.kind": ("cg.gaze_target(kind={v})", "kind", BAD_UINT32),
    "gaze_target.priority": ("cg.gaze_target(priority={v})", "priority", BAD_UINT32),
    "gaze_target.entity": ("cg.gaze_target(entity={v})", "entity", BAD_UINT32),
    "character_desc.attention_model": (
        "cg.character_desc(attention_model={v})",
        "attention_model",
        BAD_UINT32,
    ),
    "set_key_clip.key": ("blender.set_key_clip({v}, [dq], 10.0)", "key", BAD_UINT32),
    "set_key_pose.key": ("blender.set_key_pose({v}, [dq])", "key", BAD_UINT32),
    "add_camera.key": ("blender.add_camera((0, 1, 0), {v})", "key", BAD_UINT32),
    "blend_dib.max_iterations": (
        "cg.blend_dib([dq], [1.0], max_iterations={v})",
        "max_iterations",
        BAD_UINT32,
    ),
    "blend_pose_dib.max_iterations": (
        "cg.blend_pose_dib([dq], [1.0], max_iterations={v})",
        "max_iterations",
        BAD_UINT32,
    ),
}

#: Arrays of integers: each bad value inside a list.
INTEGER_ARRAYS = {
    "entity_states.ids": ("cg.entity_states([{v}])", "ids"),
    "set_base_poses.characters": ("crowd.set_base_poses([{v}], q)", "characters"),
    "set_conversation.members": ("crowd.set_conversation([{v}])", "members"),
}
BAD_IN_ARRAY = [
    (v, t) for v, t in BAD_UINT32 if v not in ("[1]", "np.True_", "1.0", "Decimal(1)")
]


def integer_fields(ctype):
    """The unsigned integer fields of a config struct: (name, bad values)."""
    fields = []
    for name, field_type in ctype._fields_:
        if field_type is ctypes.c_uint32:
            fields.append((name, BAD_UINT32))
        elif field_type is ctypes.c_uint64:
            fields.append((name, BAD_UINT64))
    return fields


def real_fields(ctype):
    return [name for name, field_type in ctype._fields_ if field_type is ctypes.c_float]


def test_integers_out_of_range_or_of_the_wrong_type_are_refused_by_name():
    batch = Batch()
    for label, (template, name, bad) in INTEGER_ARGUMENTS.items():
        for value, outcome in bad:
            batch.add(f"{label}={value}", template.format(v=value), outcome, name)
    for label, (template, name) in INTEGER_ARRAYS.items():
        for value, outcome in BAD_IN_ARRAY:
            batch.add(f"{label}=[{value}]", template.format(v=value), outcome, name)
    for value, outcome in [("np.array([0, -1])", OVERFLOW), ("np.array([2**40])", OVERFLOW),
                           ("np.array([0.0, 1.0])", TYPE), ("np.array([True])", TYPE),
                           ("{0: 1}", TYPE), ("'01'", TYPE), ("b'01'", TYPE)]:
        for label, (template, name) in INTEGER_ARRAYS.items():
            expression = template.replace("[{v}]", value)
            batch.add(f"{label}={value}", expression, outcome, name)
    # Every integer field of every config struct, through the helpers and the constructors.
    for name, bad in integer_fields(cg.CrowdConfig):
        for value, outcome in bad:
            batch.add(f"crowd_config.{name}={value}", f"cg.crowd_config({name}={value})",
                      outcome, name)
            batch.add(f"Crowd.{name}={value}", f"cg.Crowd({name}={value})", outcome, name)
    for name, bad in integer_fields(cg.ViewBlenderConfig):
        for value, outcome in bad:
            batch.add(f"view_blender_config.{name}={value}",
                      f"cg.view_blender_config({name}={value})", outcome, name)
            fields = f"**{{'joint_count': 1, 'key_count': 1, {name!r}: {value}}}"
            batch.add(f"ViewBlender.{name}={value}", f"cg.ViewBlender({fields})", outcome, name)
    batch.add("object_desc.struct_size", "cg.object_desc(struct_size=-1)", OVERFLOW,
              "struct_size")
    # A failed call changed nothing: the crowd still steps exactly as a twin that never saw
    # a bad call (the attempts above all fail).
    batch.add("unchanged after the failed calls", None, "ok")
    epilogue = textwrap.dedent(
        """
        twin = cg.Crowd(max_characters=8, max_objects=2, seed=1, max_recorded_states=100)
        assert [twin.add_character((2.0 * k, 0, 0)) for k in range(3)] == ids
        twin.add_object((0, 0, 3), look_at_height=1.5)
        twin.push_frame(0.0, states)
        twin.step(1 / 30)
        def unchanged():
            for frame in range(1, 31):
                for c in (crowd, twin):
                    states["position"][0, 2] = 0.05 * frame
                    c.push_frame(frame / 30, states)
                    c.step(1 / 30)
            assert crowd.read_joints().tobytes() == twin.read_joints().tobytes()
            assert crowd.read_gaze().tobytes() == twin.read_gaze().tobytes()
        attempt("unchanged after the failed calls", unchanged)
        """
    )
    batch.run(epilogue=epilogue)
    assert len(batch.cases) > 1000


# --- real numbers --------------------------------------------------------------------------

BAD_REAL = [
    ("'abc'", TYPE),
    ("'1.5'", TYPE),
    ("b'1'", TYPE),
    ("None", TYPE),
    ("[0.1]", TYPE),
    ("(0.1,)", TYPE),
    ("1j", TYPE),
    ("True", TYPE),
    ("np.True_", TYPE),
    ("object()", TYPE),
    ("np.array([0.1, 0.2])", TYPE),
    ("{}", TYPE),
    ("10**400", OVERFLOW),
]
#: Finite doubles out of a C float's range (float32 arguments only).
FLOAT32_OVERFLOW = [("1e39", OVERFLOW), ("-3.5e38", OVERFLOW)]
NON_FINITE_VALUES = [("nan", NON_FINITE), ("inf", NON_FINITE), ("-inf", NON_FINITE)]

#: Real arguments: label -> (expression, name, float32?, refused non-finite by C?)
REAL_ARGUMENTS = {
    "step.dt": ("crowd.step({v})", "dt", True, True),
    "begin_step.dt": ("crowd.begin_step({v})", "dt", True, True),
    "push_frame.t": ("crowd.push_frame({v}, states)", "t", False, True),
    "begin_push.t": ("crowd.begin_push({v})", "t", False, True),
    "set_impact.impact": ("crowd.set_impact(lamp, {v})", "impact", True, True),
    "set_viewer.impact": ("crowd.set_viewer((0, 1, 5), {v})", "impact", True, True),
    "add_character.heading": ("crowd.add_character((0, 0, 0), {v})", "heading", True, True),
    "add_object.impact": ("crowd.add_object((0, 0, 0), impact={v})", "impact", True, True),
    "set_character_params.attention_fraction": (
        "crowd.set_character_params(ids[0], attention_fraction={v})",
        "attention_fraction",
        True,
        True,
    ),
    "set_key_clip.frames_per_second": (
        "blender.set_key_clip(0, [dq], {v})",
        "frames_per_second",
        True,
        True,
    ),
    "evaluate.t": ("blender.evaluate(dq, (0, 0, 5), {v})", "t", False, True),
    "blend_dib.precision": ("cg.blend_dib([dq], [1.0], precision={v})", "precision", True, True),
    "blend_pose_dib.precision": (
        "cg.blend_pose_dib([dq], [1.0], precision={v})",
        "precision",
        True,
        True,
    ),
    "ViewBlender.alpha": ("cg.ViewBlender(joint_count=1, key_count=1, alpha={v})", "alpha",
                          True, True),
}


def test_real_numbers_of_the_wrong_type_or_range_are_refused_by_name():
    batch = Batch()
    for label, (template, name, single, c_refuses) in REAL_ARGUMENTS.items():
        bad = BAD_REAL + (FLOAT32_OVERFLOW if single else [])
        for value, outcome in bad:
            if value == "None" and label == "add_character.heading":
                continue  # None is the default heading
            batch.add(f"{label}={value}", template.format(v=value), outcome, name)
        if c_refuses:
            for value, outcome in NON_FINITE_VALUES:
                batch.add(f"{label}={value}", template.format(v=value), outcome)
    for name in real_fields(cg.CrowdConfig):
        for value, outcome in [("'abc'", TYPE), ("None", TYPE), ("True", TYPE),
                               ("1e39", OVERFLOW)]:
            batch.add(f"Crowd.{name}={value}", f"cg.Crowd({name}={value})", outcome, name)
        batch.add(f"Crowd.{name}=nan", f"cg.Crowd({name}=nan)", NON_FINITE)
    for name in real_fields(cg.ViewBlenderConfig):
        for value, outcome in [("'abc'", TYPE), ("1e39", OVERFLOW)]:
            batch.add(f"view_blender_config.{name}={value}",
                      f"cg.view_blender_config({name}={value})", outcome, name)
    for name in real_fields(cg.ObjectDesc):
        batch.add(f"object_desc.{name}", f"cg.object_desc({name}='x')", TYPE, name)
    for name in real_fields(cg.CharacterParams):
        batch.add(f"set_character_params.{name}",
                  f"crowd.set_character_params(ids[0], {name}=[1.0])", TYPE, name)
    # Flags (C bool) take True or False only.
    for value in ("1", "0", "'yes'", "None", "1.0"):
        batch.add(f"set_key_clip.looping={value}",
                  f"blender.set_key_clip(0, [dq], 10.0, looping={value})", TYPE, "looping")
    batch.add("looping=np.True_", "blender.set_key_clip(0, [dq], 10.0, looping=np.True_)", "ok")
    batch.run()
    assert len(batch.cases) > 250


# --- vectors and quaternions ---------------------------------------------------------------

#: Vector arguments: label -> (expression, name, whether None is meaningful (a default))
VECTOR_ARGUMENTS = {
    "add_character.position": ("crowd.add_character({v})", "position", True),
    "add_object.position": ("crowd.add_object({v})", "position", True),
    "set_viewer.position": ("crowd.set_viewer({v})", "position", False),
    "set_gaze_target.point": ("crowd.set_gaze_target(ids[0], point={v})", "point", True),
    "add_camera.direction": ("blender.add_camera({v}, 0)", "direction", False),
    "dualquat_from_rt.translation": ("cg.dualquat_from_rt((0, 0, 0, 1), {v})", "translation",
                                     False),
    "weights.viewer": ("blender.weights(dq, {v})", "viewer", False),
    "evaluate.viewer": ("blender.evaluate(dq, {v}, 0.0)", "viewer", False),
    "character_desc.position": ("cg.character_desc(position={v})", "position", False),
    "gaze_target.point": ("cg.gaze_target(point={v})", "point", False),
}
BAD_VECTOR = [
    ("(1, 2)", VALUE),
    ("(1, 2, 3, 4)", VALUE),
    ("()", VALUE),
    ("np.zeros((2, 3))", VALUE),
    ("'abc'", TYPE),
    ("b'abc'", TYPE),
    ("{1, 2, 3}", TYPE),
    ("{'x': 1, 'y': 2, 'z': 3}", TYPE),
    ("(1, 'a', 3)", TYPE),
    ("(1, None, 3)", TYPE),
    ("cg.Quat(0, 0, 0, 1)", TYPE),
    ("np.array([True, False, True])", TYPE),
    ("np.zeros(3, complex)", TYPE),
    ("memoryview(bytes(12))", TYPE),
    ("bytearray(12)", TYPE),
    ("(ctypes.c_bool * 3)()", TYPE),
    ("(1e39, 0, 0)", OVERFLOW),
    ("np.array([0, 0, -1e300])", OVERFLOW),
    ("5", VALUE),
]


def test_vectors_and_quaternions_are_checked_by_name():
    batch = Batch()
    for label, (template, name, none_is_default) in VECTOR_ARGUMENTS.items():
        for value, outcome in BAD_VECTOR:
            batch.add(f"{label}={value}", template.format(v=value), outcome, name)
        if not none_is_default:
            batch.add(f"{label}=None", template.format(v="None"), TYPE, name)
        batch.add(f"{label}=nan", template.format(v="(nan, 0, 0)"), (NON_FINITE, "ok"))
    bad_rotation = [(v, t) for v, t in BAD_VECTOR if t == TYPE and "Quat" not in v] + [
        ("(0, 0, 1)", VALUE),
        ("(0, 0, 0, 1, 0)", VALUE),
        ("cg.Vec3(0, 0, 1)", TYPE),
        ("None", TYPE),
        ("(1e39, 0, 0, 1)", OVERFLOW),
    ]
    for value, outcome in bad_rotation:
        batch.add(f"rotation={value}", f"cg.dualquat_from_rt({value}, (0, 0, 0))", outcome,
                  "rotation")
    # Foreign buffers of numbers are read by value, whatever their element type.
    for value in ("(ctypes.c_double * 3)(1, 2, 3)", "(ctypes.c_int * 3)(1, 2, 3)",
                  "array.array('d', [1, 2, 3])", "memoryview(np.array([1.0, 2, 3]))",
                  "[Decimal(1), 2, 3.0]", "cg.Vec3(1, 2, 3)", "np.array([[1, 2, 3]])"):
        batch.add(f"by value {value}",
                  f"expect_equal(cg.dualquat_to_rt(cg.dualquat_from_rt((0, 0, 0, 1), {value}))"
                  f"[1], [1, 2, 3])", "ok")
    batch.run()


# --- arrays of floats and foreign buffers --------------------------------------------------

#: Float-row arguments: label -> (expression, name, rows of, a valid value's row count)
ROW_ARGUMENTS = {
    "set_base_pose.local": ("crowd.set_base_pose(ids[0], {v})", "local", 4, 10),
    "set_base_poses.local": ("crowd.set_base_poses(ids[:1], {v})", "local", 4, 10),
    "set_key_pose.pose": ("blender.set_key_pose(0, {v})", "pose", 8, 1),
    "set_key_clip.frames": ("blender.set_key_clip(0, {v}, 10.0)", "frames", 8, 1),
    "weights.character": ("blender.weights({v}, (0, 0, 5))", "character", 8, 1),
    "evaluate.character": ("blender.evaluate({v}, (0, 0, 5), 0.0)", "character", 8, 1),
    "dualquat_to_rt.dual_quat": ("cg.dualquat_to_rt({v})", "dual_quat", 8, 1),
    "dualquat_to_matrix.dual_quat": ("cg.dualquat_to_matrix({v})", "dual_quat", 8, 1),
    "blend_dlb.inputs": ("cg.blend_dlb({v}, [1.0])", "inputs", 8, 1),
    "blend_dib.inputs": ("cg.blend_dib({v}, [1.0])", "inputs", 8, 1),
    "blend_pose_dlb.keys": ("cg.blend_pose_dlb({v}, [1.0])", "keys", 8, 1),
    "blend_pose_dib.keys": ("cg.blend_pose_dib({v}, [1.0])", "keys", 8, 1),
    "entity_states.positions": ("cg.entity_states([0], {v})", "positions", 3, 1),
}
#: Other arrays of numbers: label -> (expression, name)
NUMBER_ARGUMENTS = {
    "blend_dlb.weights": ("cg.blend_dlb([dq], {v})", "weights"),
    "blend_dib.weights": ("cg.blend_dib([dq], {v})", "weights"),
    "blend_pose_dlb.weights": ("cg.blend_pose_dlb([dq], {v})", "weights"),
    "blend_pose_dib.weights": ("cg.blend_pose_dib([dq], {v})", "weights"),
    "dualquat_from_matrix.matrix": ("cg.dualquat_from_matrix({v})", "matrix"),
    "camera_center_from_projection.projection": ("cg.camera_center_from_projection({v})",
                                                 "projection"),
}
#: Refused whatever the argument: not numbers.
NOT_NUMBERS = [
    ("'abc'", TYPE),
    ("None", TYPE),
    ("{}", TYPE),
    ("set()", TYPE),
    ("bytes(32)", TYPE),
    ("bytearray(32)", TYPE),
    ("memoryview(bytes(32))", TYPE),
    ("(ctypes.c_bool * 8)()", TYPE),
    ("(ctypes.c_char * 8)()", TYPE),
    ("(cg.Vec3 * 8)()", TYPE),
    ("(cg.GazeInfo * 2)()", TYPE),
    ("cg.GazeInfo()", TYPE),
    ("np.zeros(8, bool)", TYPE),
    ("np.zeros(8, complex)", TYPE),
    ("np.zeros(8, 'U1')", TYPE),
    ("np.zeros(2, cg.GAZE_INFO_DTYPE)", TYPE),
    ("[[1, 2], [3]]", TYPE),
    ("[1, 'a']", TYPE),
    ("[1, None]", TYPE),
    ("(x for x in range(8))", TYPE),
    ("1j", TYPE),
]


def test_float_arrays_refuse_what_is_not_numbers_and_read_foreign_buffers_by_value():
    batch = Batch()
    for label, (template, name, width, rows) in ROW_ARGUMENTS.items():
        for value, outcome in NOT_NUMBERS:
            if label == "entity_states.positions" and value in ("None", "(cg.Vec3 * 8)()"):
                continue  # no positions; Vec3 structs are positions
            batch.add(f"{label}={value}", template.format(v=value), outcome, name)
        # Not whole rows: a ctypes array of doubles is read by value (20 doubles are not
        # rows of 8 or 3 numbers), never reinterpreted as floats.
        odd = {8: 20, 4: 6, 3: 4}[width]
        batch.add(f"{label}=c_double*{odd}", template.format(v=f"(ctypes.c_double * {odd})()"),
                  VALUE, name)
        batch.add(f"{label}=c_int*{odd}", template.format(v=f"(ctypes.c_int * {odd})()"),
                  VALUE, name)
        batch.add(f"{label}=wrong last dimension",
                  template.format(v=f"np.zeros(({rows * width}, 1))"), VALUE, name)
        batch.add(f"{label}=1e39", template.format(v=f"np.full(({rows}, {width}), 1e39)"),
                  OVERFLOW, name)
        # The same values as doubles (c_double, array.array('d'), a float64 memoryview)
        # go through, converted by value: they are then whatever the call makes of them.
        good = "[0, 0, 0, 1] * 10" if width == 4 else ("[0, 0, 0]" if width == 3 else
                                                         "[0, 0, 0, 1, 0, 0, 0, 0]")
        for value in (f"(ctypes.c_double * {rows * width})(*{good})",
                      f"array.array('d', {good})", f"memoryview(np.array({good}, float))"):
            batch.add(f"{label}={value}", template.format(v=value), "ok")
    for label, (template, name) in NUMBER_ARGUMENTS.items():
        for value, outcome in NOT_NUMBERS:
            batch.add(f"{label}={value}", template.format(v=value), outcome, name)
    for value in ("np.eye(3)", "np.zeros(15)", "np.zeros((2, 8))"):
        batch.add(f"matrix {value}", f"cg.dualquat_from_matrix({value})", VALUE, "matrix")
        batch.add(f"projection {value}", f"cg.camera_center_from_projection({value})", VALUE,
                  "projection")
    # Read by value, not reinterpreted: 8 doubles are one identity dual quaternion.
    for value in ("(ctypes.c_double * 8)(*IDENTITY_DQ)", "(ctypes.c_int * 8)(*IDENTITY_DQ)",
                  "array.array('d', IDENTITY_DQ)", "array.array('f', IDENTITY_DQ)",
                  "memoryview(np.array(IDENTITY_DQ, float))", "(ctypes.c_float * 8)(*IDENTITY_DQ)",
                  "cg.DualQuat.from_buffer_copy(dq.tobytes())", "np.array(IDENTITY_DQ, '>f8')"):
        batch.add(f"identity from {value}",
                  f"expect_equal(cg.dualquat_to_rt({value})[0], [0, 0, 0, 1])", "ok")
    batch.add("20 doubles are not 10 quaternions",
              "crowd.set_base_pose(ids[0], (ctypes.c_double * 20)(*[0, 0, 0, 1] * 5))",
              "Error:INVALID_ARGUMENT", "5")
    batch.add("misaligned input is copied",
              "crowd.set_base_pose(ids[0], np.frombuffer(bytearray(1) + "
              "np.tile(np.float32([0, 0, 0, 1]), 10).tobytes(), np.float32, 40, 1))", "ok")
    batch.run()


# --- push_frame's states --------------------------------------------------------------------


def test_push_frame_refuses_what_is_not_states():
    batch = Batch()
    for value in ("{}", "set()", "'abc'", "None", "b''", "bytearray(40)", "5", "1.5",
                  "np.zeros(3)", "np.zeros((3, 10), np.float32)", "(cg.GazeInfo * 2)()",
                  "[states[0]]", "[cg.GazeInfo()]", "(s for s in [])", "{1: states}",
                  "memoryview(states)", "frozenset()", "range(3)", "dict(a=1)"):
        batch.add(f"states={value}", f"crowd.push_frame(1.0, {value})", TYPE, "states")
    batch.add("states=gaze records", "crowd.push_frame(1.0, np.zeros(2, cg.GAZE_INFO_DTYPE))",
              (TYPE, VALUE), "states")
    # push_range converts its states as push_frame does.
    for value in ("None", "5", "'abc'", "[cg.GazeInfo()]", "np.zeros(3)"):
        batch.add(f"push_range states={value}", f"crowd.push_range({value})", TYPE, "states")
    # Record arrays of another dtype are converted field by field, checked.
    records = {
        "id -1": ("'id', 'i8', -1", OVERFLOW),
        "id 2**40": ("'id', 'i8', 2**40", OVERFLOW),
        "id 0.5": ("'id', 'f8', 0.5", TYPE),
        "id True": ("'id', '?', True", TYPE),
        "flags -3": ("'flags', 'i8', -3", OVERFLOW),
        "heading text": ("'heading', 'U1', 'x'", TYPE),
        "heading 1e39": ("'heading', 'f8', 1e39", OVERFLOW),
        "position 1e39": ("'position', ('f8', (3,)), (1e39, 0, 0)", OVERFLOW),
        "position 2 numbers": ("'position', ('f8', (2,)), (1, 0)", VALUE),
        "velocity complex": ("'velocity', ('c16', (3,)), (1j, 0, 0)", TYPE),
    }
    for label, (arguments, outcome) in records.items():
        field = arguments.split(",")[0].strip("'")
        batch.add(f"records {label}", f"crowd.push_frame(1.0, records_with({arguments}))",
                  outcome, ("states", field))
    batch.add("records missing fields",
              "crowd.push_frame(1.0, np.zeros(1, [('id', 'u4')]))", VALUE,
              ("states", "record field"))
    batch.add("converted records", "crowd.push_frame(1.0, records_with('id', 'i8', ids[0]))",
              "ok")
    batch.add("empty list", "crowd.push_frame(1.0, [])", "ok")
    batch.add("one EntityState", "crowd.push_frame(1.0, cg.EntityState(), )",
              "Error:BAD_STRUCT_SIZE")
    batch.run()


# --- outputs --------------------------------------------------------------------------------

#: out= arguments: label -> (expression, shape, dtype expression)
OUTPUTS = {
    "read_joints": ("crowd.read_joints(out={o})", (30, 4), "np.float32"),
    "read_joint_deltas": ("crowd.read_joint_deltas(out={o})", (30, 4), "np.float32"),
    "read_joints range": ("crowd.read_joints(1, 1, out={o})", (10, 4), "np.float32"),
    "read_gaze": ("crowd.read_gaze(out={o})", (3,), "cg.GAZE_INFO_DTYPE"),
    "read_eyes": ("crowd.read_eyes(out={o})", (3,), "cg.EYE_INFO_DTYPE"),
    "read_eyelids": ("crowd.read_eyelids(out={o})", (3,), "cg.EYELIDS_DTYPE"),
    "read_eyelids range": ("crowd.read_eyelids(1, 2, out={o})", (2,), "cg.EYELIDS_DTYPE"),
    "weights": ("blender.weights(dq, (0, 0, 5), out={o})", (2,), "np.float32"),
    "evaluate": ("blender.evaluate(dq, (0, 0, 5), 0.0, out={o})", (1, 8), "np.float32"),
    "blend_pose_dlb": ("cg.blend_pose_dlb([dq, dq], [0.5, 0.5], out={o})", (1, 8),
                       "np.float32"),
    "blend_pose_dib": ("cg.blend_pose_dib([dq, dq], [0.5, 0.5], out={o})", (1, 8),
                       "np.float32"),
}


def test_outputs_must_be_writeable_contiguous_arrays_of_the_exact_dtype_and_shape():
    batch = Batch()
    for label, (template, shape, dtype) in OUTPUTS.items():
        records = "DTYPE" in dtype
        kinds = {
            "readonly": VALUE,
            "float64": TYPE,
            "int32": TYPE,
            "int64": TYPE,
            "bool": TYPE,
            "float16": TYPE,
            "uint8": TYPE,
            "bigendian": TYPE,
            "list": TYPE,
            "bytes": TYPE,
            "bytearray": TYPE,
            "memoryview": TYPE,
            "ctypes": TYPE,
            "column": VALUE,
        }
        if records:
            kinds.update(other_records=TYPE, reordered_records=TYPE)
        if shape[0] > 1:  # one row is contiguous whatever its stride
            kinds.update(strided=VALUE)
        if len(shape) == 2:
            kinds.update(flat=VALUE)
            if shape[0] > 1:
                kinds.update(transposed=VALUE)
        kinds.update(short=VALUE, long=VALUE)
        for kind, outcome in kinds.items():
            out = f"make_out({kind!r}, {shape}, {dtype})"
            batch.add(f"{label} out={kind}", template.format(o=out), outcome, "out")
        # The exact array is written in place and returned.
        call = template.format(o="o")
        batch.add(f"{label} out=good",
                  f"(lambda o: np.shares_memory({call}, o) or 1 / 0)(np.zeros({shape}, {dtype}))",
                  "ok")
    batch.add("read_gaze 2-D out", "crowd.read_gaze(out=np.zeros((3, 1), cg.GAZE_INFO_DTYPE))",
              VALUE, "out")
    batch.add("misaligned out",
              "crowd.read_joints(out=np.frombuffer(bytearray(481), np.float32, 120, 1)"
              ".reshape(30, 4))", VALUE, ("out", "aligned"))
    batch.run()


# --- the rest of the API's misuse ------------------------------------------------------------


def test_other_misuse_is_refused_by_name():
    batch = Batch()
    add = batch.add
    add("Crowd(config=dict)", "cg.Crowd({'max_characters': 3})", TYPE, "config")
    add("Crowd(config=ViewBlenderConfig)", "cg.Crowd(cg.view_blender_config())", TYPE, "config")
    add("Crowd(unknown field)", "cg.Crowd(no_such_field=1)", TYPE, "no_such_field")
    add("Crowd(config, bad field)", "cg.Crowd(cg.crowd_config(), threads=-1)", OVERFLOW,
        "threads")
    add("ViewBlender(config=Crowd config)", "cg.ViewBlender(cg.crowd_config())", TYPE, "config")
    add("ViewBlender(config, key_count)", "cg.ViewBlender(cg.view_blender_config("
        "joint_count=1), key_count=2**32)", OVERFLOW, "key_count")
    add("add_character desc wrong", "crowd.add_character(desc=cg.object_desc())", TYPE, "desc")
    add("add_character desc and position", "crowd.add_character((1, 0, 0), "
        "desc=cg.character_desc())", TYPE, "desc")
    add("add_character chain wrong", "crowd.add_character(chain=5)", TYPE, "chain")
    add("add_character chain struct", "crowd.add_character(chain=cg.ChainJoint())", TYPE,
        "chain")
    add("add_object desc wrong", "crowd.add_object(desc=cg.character_desc())", TYPE, "desc")
    add("add_object unknown field", "crowd.add_object(attention_model=1)", TYPE,
        "attention_model")
    add("set_character_params params wrong", "crowd.set_character_params(ids[0], "
        "params=cg.gaze_target())", TYPE, "params")
    add("set_character_params both", "crowd.set_character_params(ids[0], "
        "params=crowd.character_params(ids[0]), attention_fraction=0.5)", TYPE, "params")
    add("set_gaze_target target wrong", "crowd.set_gaze_target(ids[0], target=5)", TYPE,
        "target")
    add("set_gaze_target target and point", "crowd.set_gaze_target(ids[0], (0, 0, 1), "
        "target=cg.gaze_target())", TYPE, "target")
    add("set_gaze_target neither", "crowd.set_gaze_target(ids[0])", TYPE, "point")
    add("set_gaze_target both", "crowd.set_gaze_target(ids[0], (0, 0, 1), entity=lamp)", TYPE,
        "entity")
    add("gaze_target unknown field", "cg.gaze_target(target=1)", TYPE, "target")
    add("character_desc chain int", "cg.character_desc(chain=3)", TYPE, "chain")
    add("not initialised", "cg.Crowd.__new__(cg.Crowd).step(0.1)", VALUE, "initialised")
    add("not initialised close", "cg.Crowd.__new__(cg.Crowd).close()", "ok")
    add("not initialised blender", "cg.ViewBlender.__new__(cg.ViewBlender).weights(dq, "
        "(0, 0, 5))", VALUE, "initialised")
    add("joint_count read-only", "setattr(blender, 'joint_count', 0)", "AttributeError")
    add("key_count read-only", "setattr(blender, 'key_count', 100)", "AttributeError")
    add("blend_dlb counts", "cg.blend_dlb([dq, dq], [1.0])", VALUE, "weights")
    add("blend_pose keys split", "cg.blend_pose_dlb([dq, dq, dq], [0.5, 0.5])", VALUE,
        "keys")
    add("set_key_clip not whole frames", "cg.ViewBlender(joint_count=2, key_count=1)"
        ".set_key_clip(0, [dq, dq, dq], 10.0)", VALUE, "frames")
    batch.run()


def test_hostile_conversations_are_refused_and_change_nothing():
    batch = Batch()
    add = batch.add
    invalid, not_found = "Error:INVALID_ARGUMENT", "Error:NOT_FOUND"
    # Members the library refuses (after the binding's checks passed).
    add("members of one", "crowd.set_conversation([ids[0]])", invalid, "not 1")
    add("members an int", "crowd.set_conversation(ids[0])", invalid, "not 1")
    add("members of nine", "crowd.set_conversation([ids[0], ids[1]] * 4 + [ids[2]])", invalid,
        "not 9")
    add("members of 2**16", "crowd.set_conversation(np.arange(2**16) % 3)", invalid, "65536")
    add("members twice", "crowd.set_conversation([ids[2], ids[2]])", invalid, "twice")
    add("members an object", "crowd.set_conversation([ids[2], lamp])", invalid, "object")
    add("members already grouped", "crowd.set_conversation([ids[2], ids[0]])", invalid,
        "already")
    add("members unknown", "crowd.set_conversation([ids[2], 2**32 - 1])", not_found,
        "4294967295")
    add("members a removed character", "crowd.set_conversation([ids[2], gone])", not_found)
    # Members the binding refuses before the call, naming them.
    add("members a string", "crowd.set_conversation('01')", TYPE, "members")
    add("members a dict", "crowd.set_conversation({ids[1]: ids[2]})", TYPE, "members")
    add("members floats", "crowd.set_conversation(np.array([0.0, 1.0]))", TYPE, "members")
    add("members bools", "crowd.set_conversation([True, False])", TYPE, "members")
    add("members 2-D", "crowd.set_conversation(np.array([[ids[1]], [ids[2]]], np.int64))",
        invalid, "already")
    add("members int64 too large", "crowd.set_conversation(np.array([ids[1], 2**40]))",
        OVERFLOW, "members")
    add("members big-endian", "crowd.set_conversation(np.array([ids[2], 9], '>u4'))",
        not_found, "9")
    add("members a generator", "crowd.set_conversation(i for i in ids)", TYPE, "members")
    # Groups and characters the library does not know.
    for value in ("group + 1", "2**32 - 1", "0 if group else 1", "ended"):
        add(f"remove_conversation({value})", f"crowd.remove_conversation({value})", not_found,
            "conversation")
    add("conversation_of(gone)", "crowd.conversation_of(gone)", not_found)
    add("conversation_of(2**32 - 1)", "crowd.conversation_of(2**32 - 1)", not_found)
    add("conversation_of(lamp)", "crowd.conversation_of(lamp)", invalid, "object")
    # A failed call changed nothing: the group and the gaze are those of a twin that never
    # saw a bad call.
    add("unchanged after the failed calls", None, "ok")
    setup = SETUP + textwrap.dedent(
        """
        gone = crowd.add_character((9, 0, 9))
        crowd.remove_entity(gone)
        ended = crowd.set_conversation([ids[1], ids[2]])
        crowd.remove_conversation(ended)
        group = crowd.set_conversation([ids[0], ids[1]])
        """
    )
    epilogue = textwrap.dedent(
        """
        twin = cg.Crowd(max_characters=8, max_objects=2, seed=1, max_recorded_states=100)
        assert [twin.add_character((2.0 * k, 0, 0)) for k in range(3)] == ids
        twin.add_object((0, 0, 3), look_at_height=1.5)
        twin.push_frame(0.0, states)
        twin.step(1 / 30)
        twin.remove_entity(twin.add_character((9, 0, 9)))
        twin.remove_conversation(twin.set_conversation([ids[1], ids[2]]))
        assert twin.set_conversation([ids[0], ids[1]]) == group
        def unchanged():
            assert [crowd.conversation_of(i) for i in ids] == [group, group, None]
            for frame in range(1, 31):
                for c in (crowd, twin):
                    states["flags"] = cg.CG_STATE_TALKING if frame < 15 else 0
                    c.push_frame(frame / 30, states)
                    c.step(1 / 30)
            assert crowd.read_joints().tobytes() == twin.read_joints().tobytes()
            assert crowd.read_gaze().tobytes() == twin.read_gaze().tobytes()
        attempt("unchanged after the failed calls", unchanged)
        """
    )
    batch.run(setup=setup, epilogue=epilogue)


# --- ownership: copies, pickles, re-initialisation ----------------------------------------


MAKE = {
    "Crowd": "cg.Crowd(max_characters=4, seed=1)",
    "ViewBlender": "cg.ViewBlender(joint_count=1, key_count=1)",
}
USE = {
    "Crowd": "obj.add_character((0, 0, 0)); obj.step(0.1); obj.read_joints()",
    "ViewBlender": "obj.set_key_pose(0, [cg.dualquat_from_rt((0, 0, 0, 1), (0, 0, 0))])",
}


@pytest.mark.parametrize("kind", list(MAKE))
@pytest.mark.parametrize(
    "duplicate",
    [
        "copy.copy(obj)",
        "copy.deepcopy(obj)",
        "copy.deepcopy([obj])",
        "pickle.dumps(obj)",
        "pickle.dumps(obj, protocol=0)",
        "pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)",
        "obj.__reduce_ex__(2)",
        "obj.__getstate__()",
    ],
)
def test_copies_and_pickles_are_refused_and_nothing_is_destroyed_twice(kind, duplicate):
    result = run_alone(
        f"""
        obj = {MAKE[kind]}
        try:
            twin = {duplicate}
            outcome, message = "ok", ""
        except Exception as error:
            outcome, message = outcome(error), str(error)
            twin = None
        {USE[kind]}
        del twin
        gc.collect()
        obj.close()
        del obj
        gc.collect()
        print(json.dumps({{"outcome": outcome, "message": message}}))
        """
    )
    assert result["outcome"] == "TypeError", result
    assert kind in result["message"] and ("copied" in result["message"]
                                          or "pickled" in result["message"])


@pytest.mark.parametrize("kind", list(MAKE))
def test_init_again_is_refused_on_a_live_or_closed_object(kind):
    result = run_alone(
        f"""
        obj = {MAKE[kind]}
        outcomes = []
        for again in (lambda: obj.__init__(), lambda: type(obj).__init__(obj, None)):
            try:
                again()
                outcomes.append(["ok", ""])
            except Exception as error:
                outcomes.append([outcome(error), str(error)])
        {USE[kind]}
        obj.close()
        try:
            obj.__init__()
            outcomes.append(["ok", ""])
        except Exception as error:
            outcomes.append([outcome(error), str(error)])
        del obj
        gc.collect()
        print(json.dumps({{"outcomes": outcomes}}))
        """
    )
    for outcome, message in result["outcomes"]:
        assert outcome == "RuntimeError" and "already initialised" in message, result


# --- closing under a call -------------------------------------------------------------------

REENTRANT = {
    "step dt __float__": ("crowd", "crowd.step(Closer(crowd))"),
    "set_impact impact __float__": ("crowd", "crowd.set_impact(0, Closer(crowd))"),
    "remove_entity __index__": ("crowd", "crowd.remove_entity(Closer(crowd))"),
    "read_joints first __index__": ("crowd", "crowd.read_joints(Closer(crowd))"),
    "read_eyes count __index__": ("crowd", "crowd.read_eyes(0, Closer(crowd))"),
    "read_eyelids first __index__": ("crowd", "crowd.read_eyelids(Closer(crowd))"),
    "set_viewer position element": ("crowd", "crowd.set_viewer((Closer(crowd), 1, 2))"),
    "set_base_pose local element": (
        "crowd", "crowd.set_base_pose(0, [[0, 0, 0, Closer(crowd)]] + [[0, 0, 0, 1]] * 9)"),
    "push_frame states sequence": ("crowd", "crowd.push_frame(1.0, ClosingList(crowd))"),
    "push_frame t __float__": ("crowd", "crowd.push_frame(Closer(crowd), [])"),
    "set_key_clip key __index__": (
        "blender", "blender.set_key_clip(Closer(blender), [dq], 10.0)"),
    "set_key_clip fps __float__": (
        "blender", "blender.set_key_clip(0, [dq], Closer(blender))"),
    "evaluate t __float__": ("blender", "blender.evaluate(dq, (0, 0, 5), Closer(blender))"),
    "weights viewer element": ("blender", "blender.weights(dq, (0, 0, Closer(blender)))"),
    "add_camera key __index__": ("blender", "blender.add_camera((0, 0, 1), Closer(blender))"),
    "set_conversation members element": (
        "crowd", "crowd.set_conversation(np.array([0, Closer(crowd)], dtype=object))"),
    "remove_conversation group __index__": (
        "crowd", "crowd.remove_conversation(Closer(crowd))"),
    "conversation_of character __index__": ("crowd", "crowd.conversation_of(Closer(crowd))"),
}


@pytest.mark.parametrize("case", list(REENTRANT))
def test_an_argument_that_closes_the_object_while_converted_cannot_free_it_under_the_call(case):
    owner, call = REENTRANT[case]
    result = run_alone(
        f"""
        class Closer:
            # A number whose conversion closes the object it is passed to.
            def __init__(self, target):
                self.target = target
            def __float__(self):
                self.target.close()
                return 0.1
            def __index__(self):
                self.target.close()
                return 0

        class ClosingList(list):
            def __init__(self, target):
                super().__init__()
                self.target = target
            def __iter__(self):
                self.target.close()
                return super().__iter__()
            def __len__(self):
                self.target.close()
                return 0

        crowd = cg.Crowd(max_characters=8, seed=1)
        crowd.add_character((0, 0, 0))
        crowd.step(0.1)
        dq = cg.dualquat_from_rt((0, 0, 0, 1), (0, 0, 0))
        blender = cg.ViewBlender(joint_count=1, key_count=1)
        blender.set_key_pose(0, [dq])
        blender.add_camera((0, 0, 1), 0)
        try:
            {call}
            outcome, message = "ok", ""
        except Exception as error:
            outcome, message = outcome(error), str(error)
        closed = {owner}.closed
        {owner}.close()  # closing again is fine
        gc.collect()
        print(json.dumps({{"outcome": outcome, "message": message, "closed": closed}}))
        """
    )
    assert result["closed"], result
    assert result["outcome"] == "ValueError" and "closed" in result["message"], result


def test_close_from_inside_a_call_on_the_same_thread_raises():
    result = run_alone(
        """
        crowd = cg.Crowd(max_characters=2)
        outcomes = []
        with crowd._call("test", exclusive=False):  # as a call in flight does
            for action in (crowd.close, lambda: crowd.step(0.1)):
                try:
                    action()
                    outcomes.append(["ok", ""])
                except Exception as error:
                    outcomes.append([outcome(error), str(error)])
        crowd.step(0.1)  # the crowd is intact
        crowd.close()
        print(json.dumps({"outcomes": outcomes, "closed": crowd.closed}))
        """
    )
    assert result["closed"]
    assert [o for o, _ in result["outcomes"]] == ["RuntimeError", "RuntimeError"], result
    assert "Crowd.close" in result["outcomes"][0][1]
    assert "in flight" in result["outcomes"][0][1]


CONCURRENT_CLOSE = """
import threading, time
log = []
running = threading.Event()


def worker(call):
    while True:
        began = time.perf_counter()
        try:
            running.set()
            call()
        except ValueError as error:
            log.append(["closed", began, time.perf_counter(), str(error)])
            return
        except BaseException as error:
            log.append(["error", began, time.perf_counter(), repr(error)])
            return
        log.append(["ok", began, time.perf_counter(), ""])


threads = [threading.Thread(target=worker, args=(call,)) for call in CALLS]
for thread in threads:
    thread.start()
running.wait()
time.sleep(DELAY)
closers = [threading.Thread(target=OBJ.close) for _ in range(CLOSERS)]
began = time.perf_counter()
for closer in closers:
    closer.start()
OBJ.close()
closed = time.perf_counter()
for thread in threads + closers:
    thread.join(60)
print(json.dumps({"log": log, "began": began, "closed": closed, "threads": len(threads)}))
"""


def check_concurrent_close(result: dict) -> None:
    log = result["log"]
    outcomes = [entry[0] for entry in log]
    assert "error" not in outcomes, log
    # Every worker stopped with a clean "closed" error (no crash), and no call that began
    # after close() returned succeeded.
    assert outcomes.count("closed") == result["threads"], outcomes
    assert all("closed" in entry[3] for entry in log if entry[0] == "closed")
    assert not [entry for entry in log if entry[0] == "ok" and entry[1] > result["closed"]]
    assert outcomes.count("ok") >= 1


def test_close_from_another_thread_waits_for_the_call_in_flight():
    result = run_alone(
        """
        crowd = cg.Crowd(max_characters=2)
        holding = threading.Event()
        times = {}
        def in_flight():
            with crowd._call("test"):  # exactly as a read in flight holds the crowd
                holding.set()
                time.sleep(0.3)
                times["released"] = time.perf_counter()
        thread = threading.Thread(target=in_flight)
        thread.start()
        holding.wait()
        crowd.close()
        times["closed"] = time.perf_counter()
        thread.join()
        print(json.dumps(times))
        """
    )
    assert result["closed"] >= result["released"], result


def test_close_from_another_thread_during_steps_of_2000_characters():
    result = run_alone(
        textwrap.dedent(
            """
            crowd = cg.Crowd(max_characters=2000, max_objects=0, seed=1)
            for i in range(2000):
                crowd.add_character((float(i % 50), 0.0, float(i // 50)))
            OBJ, CALLS, DELAY, CLOSERS = crowd, [lambda: crowd.step(1 / 30)], 0.02, 0
            """
        )
        + CONCURRENT_CLOSE
    )
    check_concurrent_close(result)


def test_concurrent_closes_steps_and_reads_never_use_a_freed_crowd():
    result = run_alone(
        textwrap.dedent(
            """
            crowd = cg.Crowd(max_characters=2000, max_objects=0, seed=1)
            for i in range(2000):
                crowd.add_character((float(i % 50), 0.0, float(i // 50)))
            out = np.zeros((20000, 4), np.float32)
            OBJ, DELAY, CLOSERS = crowd, 0.02, 3
            CALLS = [lambda: crowd.step(1 / 30), lambda: crowd.read_joints(out=out),
                     lambda: crowd.read_gaze(), lambda: len(crowd)]
            """
        )
        + CONCURRENT_CLOSE
    )
    check_concurrent_close(result)


def test_close_during_ranged_steps_on_worker_threads():
    result = run_alone(
        """
        crowd = cg.Crowd(max_characters=2000, max_objects=0, seed=1)
        for i in range(2000):
            crowd.add_character((float(i % 50), 0.0, float(i // 50)))
        crowd.begin_step(1 / 30)
        outcomes = []
        def worker(first):
            try:
                crowd.step_range(first, 1000)
                outcomes.append("ok")
            except ValueError as error:
                outcomes.append("closed" if "closed" in str(error) else repr(error))
            except BaseException as error:
                outcomes.append(repr(error))
        threads = [threading.Thread(target=worker, args=(f,)) for f in (0, 1000)]
        for thread in threads:
            thread.start()
        crowd.close()
        for thread in threads:
            thread.join(60)
        print(json.dumps({"outcomes": outcomes}))
        """
    )
    assert sorted(result["outcomes"]) in (
        ["closed", "closed"], ["closed", "ok"], ["ok", "ok"]
    ), result


def test_close_from_another_thread_waits_for_running_blender_evaluations():
    result = run_alone(
        textwrap.dedent(
            """
            joints = 20000
            blender = cg.ViewBlender(joint_count=joints, key_count=2,
                                     method=cg.BlendMethod.DIB)
            pose = np.tile(cg.dualquat_from_rt((0, 0, 0, 1), (0, 1, 0)), (joints, 1))
            for key, direction in enumerate([(0, 0, 1), (1, 0, 0)]):
                blender.set_key_pose(key, pose)
                blender.add_camera(direction, key)
            character = cg.dualquat_from_rt((0, 0, 0, 1), (0, 0, 0))
            outs = [np.zeros((joints, 8), np.float32) for _ in range(2)]
            OBJ, DELAY, CLOSERS = blender, 0.02, 1
            CALLS = [lambda o=o: blender.evaluate(character, (1, 0, 1), 0.0, out=o)
                     for o in outs]
            """
        )
        + CONCURRENT_CLOSE
    )
    check_concurrent_close(result)


# --- outputs that must never be written: read-only memory ---------------------------------

READ_ONLY_OUTPUTS = {
    "read_gaze": ("crowd.read_gaze(out=out)", "cg.GAZE_INFO_DTYPE", (3,)),
    "read_eyes": ("crowd.read_eyes(out=out)", "cg.EYE_INFO_DTYPE", (3,)),
    "read_eyelids": ("crowd.read_eyelids(out=out)", "cg.EYELIDS_DTYPE", (3,)),
    "read_joints": ("crowd.read_joints(out=out)", "np.float32", (30, 4)),
    "read_joint_deltas": ("crowd.read_joint_deltas(out=out)", "np.float32", (30, 4)),
    "weights": ("blender.weights(dq, (0, 0, 5), out=out)", "np.float32", (2,)),
    "evaluate": ("blender.evaluate(dq, (0, 0, 5), 0.0, out=out)", "np.float32", (1, 8)),
}


@pytest.mark.parametrize("target", list(READ_ONLY_OUTPUTS))
@pytest.mark.parametrize("memory", ["memmap", "bytes"])
def test_read_only_memory_is_never_written(target, memory):
    call, dtype, shape = READ_ONLY_OUTPUTS[target]
    if memory == "memmap":
        make = textwrap.dedent(
            f"""
            path = os.path.join(tempfile.mkdtemp(), "out.bin")
            np.zeros({shape}, {dtype}).tofile(path)
            out = np.memmap(path, {dtype}, mode="r", shape={shape})
            """
        )
        unchanged = f"bool((np.fromfile(path, {dtype}) == np.zeros(1, {dtype})).all())"
    else:
        make = textwrap.dedent(
            f"""
            backing = bytes(np.zeros({shape}, {dtype}).nbytes)
            out = np.frombuffer(backing, {dtype}).reshape({shape})
            """
        )
        unchanged = "backing == bytes(len(backing))"
    result = run_alone(
        SETUP
        + make
        + textwrap.dedent(
            f"""
            try:
                {call}
                outcome, message = "ok", ""
            except Exception as error:
                outcome, message = outcome(error), str(error)
            print(json.dumps({{"outcome": outcome, "message": message,
                              "unchanged": {unchanged}}}))
            """
        )
    )
    assert result["outcome"] == "ValueError", result
    assert "out is read-only" in result["message"], result
    assert result["unchanged"], result


@pytest.mark.parametrize("target", ["read_gaze", "read_eyes", "read_eyelids", "read_joints"])
def test_bytearray_backed_outputs_only_of_the_exact_dtype(target):
    call, dtype, shape = READ_ONLY_OUTPUTS[target]
    result = run_alone(
        SETUP
        + textwrap.dedent(
            f"""
            outcomes = []
            backing = bytearray(np.zeros({shape}, {dtype}).nbytes)
            for out in (np.frombuffer(backing, {dtype}).reshape({shape}),  # fits: written
                        np.frombuffer(backing, np.uint8),
                        np.frombuffer(backing, np.int32),
                        np.frombuffer(bytearray(len(backing) + 1), {dtype}, offset=1,
                                      count=int(np.prod({shape}))).reshape({shape})):
                try:
                    result = {call}
                    outcomes.append(["ok", ""])
                except Exception as error:
                    outcomes.append([outcome(error), str(error)])
            print(json.dumps({{"outcomes": outcomes, "written": any(backing)}}))
            """
        )
    )
    kinds = [o for o, _ in result["outcomes"]]
    assert kinds == ["ok", "TypeError", "TypeError", "ValueError"], result
    assert all("out" in message for kind, message in result["outcomes"] if kind != "ok")
    assert result["written"]
