"""``crowdgaze.Rig``: skeletons as engines ship them (Mixamo, Unreal 5, a BVH file) map to a
gaze chain in one call with no overrides; the per-frame conversions round-trip; a crowd
turns the head of a rigged character towards a target; hostile arguments raise the
package's errors and crash nothing."""

from __future__ import annotations

import copy
import pickle
import textwrap
import threading
from pathlib import Path

import numpy as np
import pytest
from conftest import REPOSITORY
from test_hostile import CONCURRENT_CLOSE, check_concurrent_close, run_alone

import crowdgaze as cg

# --- skeletons ----------------------------------------------------------------------------

#: A Mixamo FBX skeleton: Y up, facing +Z, centimetres, identity rest rotations.
MIXAMO = [
    ("mixamorig:Hips", None, (0, 98, 0)),
    ("mixamorig:Spine", "mixamorig:Hips", (0, 7, 0)),
    ("mixamorig:Spine1", "mixamorig:Spine", (0, 16, -1)),
    ("mixamorig:Spine2", "mixamorig:Spine1", (0, 16, -1)),
    ("mixamorig:Neck", "mixamorig:Spine2", (0, 9, -1)),
    ("mixamorig:Head", "mixamorig:Neck", (0, 14, 3)),
    ("mixamorig:HeadTop_End", "mixamorig:Head", (0, 18, 0)),
    ("mixamorig:LeftEye", "mixamorig:Head", (3.2, 8, 9)),
    ("mixamorig:RightEye", "mixamorig:Head", (-3.2, 8, 9)),
    ("mixamorig:LeftShoulder", "mixamorig:Spine2", (2.5, 6, 2)),
    ("mixamorig:LeftArm", "mixamorig:LeftShoulder", (14.5, -1, -3)),
    ("mixamorig:LeftForeArm", "mixamorig:LeftArm", (28, 0, -1)),
    ("mixamorig:RightShoulder", "mixamorig:Spine2", (-2.5, 6, 2)),
    ("mixamorig:RightArm", "mixamorig:RightShoulder", (-14.5, -1, -3)),
    ("mixamorig:RightForeArm", "mixamorig:RightArm", (-28, 0, -1)),
    ("mixamorig:LeftUpLeg", "mixamorig:Hips", (9, -5, 0)),
    ("mixamorig:LeftLeg", "mixamorig:LeftUpLeg", (0.5, -41, 1)),
    ("mixamorig:LeftFoot", "mixamorig:LeftLeg", (0.5, -43, -4)),
    ("mixamorig:LeftToeBase", "mixamorig:LeftFoot", (0.5, -7, 13)),
    ("mixamorig:RightUpLeg", "mixamorig:Hips", (-9, -5, 0)),
    ("mixamorig:RightLeg", "mixamorig:RightUpLeg", (-0.5, -41, 1)),
    ("mixamorig:RightFoot", "mixamorig:RightLeg", (-0.5, -43, -4)),
    ("mixamorig:RightToeBase", "mixamorig:RightFoot", (-0.5, -7, 13)),
]

#: An Unreal Engine 5 mannequin (Manny): Z up, facing +Y, centimetres (the right-handed
#: reading, `_l` bones on -X), no eye bones.
UE5 = [
    ("root", None, (0, 0, 0)),
    ("pelvis", "root", (0, 0, 98)),
    ("spine_01", "pelvis", (0, 0, 7)),
    ("spine_02", "spine_01", (0, -0.5, 8)),
    ("spine_03", "spine_02", (0, -0.5, 8)),
    ("spine_04", "spine_03", (0, -0.5, 8)),
    ("spine_05", "spine_04", (0, -0.5, 8)),
    ("neck_01", "spine_05", (0, -1, 9)),
    ("neck_02", "neck_01", (0, 1.5, 7)),
    ("head", "neck_02", (0, 1.5, 7)),
    ("clavicle_l", "spine_05", (-2.5, 2, 6)),
    ("upperarm_l", "clavicle_l", (-14.5, -3, -1)),
    ("lowerarm_l", "upperarm_l", (-28, -1, 0)),
    ("clavicle_r", "spine_05", (2.5, 2, 6)),
    ("upperarm_r", "clavicle_r", (14.5, -3, -1)),
    ("lowerarm_r", "upperarm_r", (28, -1, 0)),
    ("thigh_l", "pelvis", (-9, 0, -5)),
    ("calf_l", "thigh_l", (-0.5, 1, -41)),
    ("foot_l", "calf_l", (-0.5, -4, -43)),
    ("ball_l", "foot_l", (-0.5, 13, -7)),
    ("thigh_r", "pelvis", (9, 0, -5)),
    ("calf_r", "thigh_r", (0.5, 1, -41)),
    ("foot_r", "calf_r", (0.5, -4, -43)),
    ("ball_r", "foot_r", (0.5, 13, -7)),
]


def skeleton(bones):
    """``(names, parents, translations)`` of a list of ``(name, parent name, offset)``."""
    names = [name for name, _, _ in bones]
    parents = [None if parent is None else names.index(parent) for _, parent, _ in bones]
    translations = np.array([offset for _, _, offset in bones], dtype=np.float64)
    return names, parents, translations


def rest(count):
    """``count`` identity rotations, ``(count, 4)`` float32."""
    return np.tile(np.float32([0, 0, 0, 1]), (count, 1))


def random_rotations(count, seed, spread=0.3):
    """``count`` unit quaternions near identity (x y z w), float32."""
    generator = np.random.default_rng(seed)
    q = np.concatenate([generator.normal(0, spread, (count, 3)), np.ones((count, 1))], axis=1)
    return (q / np.linalg.norm(q, axis=1, keepdims=True)).astype(np.float32)


def multiply(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ])


def rotate(q, v):
    p = multiply(multiply(q, np.append(v, 0.0)), np.array([-q[0], -q[1], -q[2], q[3]]))
    return p[:3]


def forward_kinematics(locals_, parents, translations):
    """Each bone's rotation and position relative to the character."""
    rotations, positions = [], []
    for bone, parent in enumerate(parents):
        local = np.asarray(locals_[bone], dtype=np.float64)
        offset = np.asarray(translations[bone], dtype=np.float64)
        if parent is None or parent < 0:
            rotations.append(local)
            positions.append(offset)
        else:
            rotations.append(multiply(rotations[parent], local))
            positions.append(positions[parent] + rotate(rotations[parent], offset))
    return rotations, positions


def angle_between(a, b):
    cosine = np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b))
    return float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))


def same_rotations(a, b, tolerance=1e-4):
    """Whether the quaternions of ``a`` and ``b`` are the same rotations (q and -q)."""
    dots = np.abs(np.sum(np.asarray(a, np.float64) * np.asarray(b, np.float64), axis=1))
    return bool(np.all(dots > 1 - tolerance))


@pytest.fixture
def mixamo():
    names, parents, translations = skeleton(MIXAMO)
    with cg.Rig(names, parents, translations, units_per_metre=100) as rig:
        yield rig


# --- mapping ------------------------------------------------------------------------------


def test_a_mixamo_skeleton_maps_with_no_overrides(mixamo):
    names, _, _ = skeleton(MIXAMO)
    assert (mixamo.bone_count, mixamo.joint_count) == (len(MIXAMO), 7)
    chain = [names[bone] for bone in mixamo.chain_bones]
    assert chain == [
        "mixamorig:Spine", "mixamorig:Spine1", "mixamorig:Spine2", "mixamorig:Neck",
        "mixamorig:Head", "mixamorig:LeftEye", "mixamorig:RightEye",
    ]
    assert mixamo.chain_bones.dtype == np.uint32
    roles = mixamo.roles
    assert roles.dtype == np.uint32 and roles.shape == (len(MIXAMO),)
    expected = {
        "mixamorig:Hips": cg.BoneRole.ROOT,
        "mixamorig:Spine": cg.BoneRole.SPINE,
        "mixamorig:Spine2": cg.BoneRole.SPINE,
        "mixamorig:Neck": cg.BoneRole.NECK,
        "mixamorig:Head": cg.BoneRole.HEAD,
        "mixamorig:LeftEye": cg.BoneRole.LEFT_EYE,
        "mixamorig:RightEye": cg.BoneRole.RIGHT_EYE,
        "mixamorig:LeftArm": cg.BoneRole.NONE,
        "mixamorig:RightUpLeg": cg.BoneRole.NONE,
    }
    for name, role in expected.items():
        assert roles[names.index(name)] == role, name
    assert cg.BoneRole(int(roles[names.index("mixamorig:Head")])) is cg.BoneRole.HEAD
    report = mixamo.report
    first = report.splitlines()[0]
    assert first.startswith("gaze chain of 7 joints") and "'mixamorig:Hips'" in first
    assert "up +Y, forward +Z" in report and "'mixamorig:LeftEye'" in report
    chain_desc = mixamo.chain
    assert isinstance(chain_desc, cg.ChainDesc) and chain_desc.joint_count == 7
    assert [chain_desc.joints[i].role for i in range(7)] == [
        cg.JointRole.SPINE, cg.JointRole.SPINE, cg.JointRole.SPINE, cg.JointRole.CERVICAL,
        cg.JointRole.HEAD, cg.JointRole.LEFT_EYE, cg.JointRole.RIGHT_EYE,
    ]
    assert repr(mixamo) == f"<crowdgaze.Rig: {len(MIXAMO)} bones, a chain of 7 joints>"


def test_an_unreal_5_skeleton_maps_with_no_overrides():
    names, parents, translations = skeleton(UE5)
    crowd = cg.Crowd(up_axis=cg.Axis.POSITIVE_Z, forward_axis=cg.Axis.POSITIVE_Y,
                     units_per_metre=100)
    rig = cg.Rig(names, np.array([-1 if p is None else p for p in parents]), translations,
                 units_per_metre=100, crowd=crowd)
    assert [names[b] for b in rig.chain_bones] == [
        "spine_01", "spine_02", "spine_03", "spine_04", "spine_05", "neck_01", "neck_02",
        "head",
    ]
    roles = rig.roles
    assert roles[names.index("pelvis")] == cg.BoneRole.ROOT
    assert roles[names.index("neck_02")] == cg.BoneRole.NECK
    assert roles[names.index("clavicle_l")] == cg.BoneRole.NONE
    assert roles[names.index("thigh_r")] == cg.BoneRole.NONE
    report = rig.report
    assert report.startswith("gaze chain of 8 joints: 5 spine, 2 neck, head; hangs from 'pelvis'")
    assert "up +Z, forward +Y" in report
    # The chain goes into the crowd as it is.
    character = crowd.add_character((0, 0, 0), chain=rig.chain)
    assert crowd.joint_total() == 8 and crowd.row_of(character) == 0


def test_given_axes_and_bone_map_overrides():
    names, parents, translations = skeleton(MIXAMO)
    names[5] = "Skull"  # the head under a name no rule reads
    with pytest.raises(cg.InvalidArgumentError) as info:
        cg.Rig(names, parents, translations, units_per_metre=100)
    assert info.value.function == "cg_rig_create" and "head" in str(info.value)
    for bone_map in ("Skull=head", {"Skull": "head"}, {"Skull": cg.BoneRole.HEAD}):
        rig = cg.Rig(names, parents, translations, units_per_metre=100, bone_map=bone_map,
                     up=cg.Axis.POSITIVE_Y, forward=cg.CG_AXIS_POSITIVE_Z)
        assert names[rig.chain_bones[4]] == "Skull", bone_map
        assert "'Skull' (override)" in rig.report
        assert "forward +Z (given)" in rig.report
    # An override takes a bone out of the chain.
    rig = cg.Rig(names, parents, translations, units_per_metre=100,
                 bone_map={"Skull": "head", "mixamorig:LeftEye": "none",
                           "mixamorig:RightEye": cg.BoneRole.NONE})
    assert rig.joint_count == 5


def test_a_bvh_skeleton_maps_in_one_call():
    folders = [REPOSITORY.parent / "shared" / "data" / "bvh", Path("/work/shared/data/bvh")]
    files = next((sorted(f.glob("*.bvh")) for f in folders if f.is_dir()), [])
    if not files:
        pytest.skip("no BVH files in shared/data/bvh")
    for path in files:
        names, parents, offsets = parse_bvh_hierarchy(path.read_text())
        rig = cg.Rig(names, parents, offsets)
        chain = [names[b] for b in rig.chain_bones]
        assert chain[-1] == "Head" and "Neck" in chain and chain[0].startswith("Spine"), path
        assert rig.report.startswith(f"gaze chain of {len(chain)} joints"), path
        assert "hangs from 'Hips'" in rig.report
        pose = rig.base_pose(rest(len(names)))
        assert pose.shape == (len(chain), 4)


def parse_bvh_hierarchy(text):
    """The bones of a BVH file's HIERARCHY: names (an ``End Site`` named after its parent),
    parent indices (-1 for the root) and OFFSETs."""
    tokens = text.split("MOTION")[0].split()
    names, parents, offsets, stack = [], [], [], []
    pending = -1
    index = 0
    while index < len(tokens):
        token = tokens[index]
        if token in ("ROOT", "JOINT", "End"):
            name = tokens[index + 1] if token != "End" else f"{names[stack[-1]]}_End"
            names.append(name)
            parents.append(stack[-1] if stack else -1)
            pending = len(names) - 1
            index += 2
        elif token == "{":
            stack.append(pending)
            index += 1
        elif token == "}":
            stack.pop()
            index += 1
        elif token == "OFFSET":
            offsets.append([float(x) for x in tokens[index + 1:index + 4]])
            index += 4
        else:
            index += 1
    assert len(names) == len(offsets) > 10 and not stack
    return names, parents, offsets


# --- each frame ---------------------------------------------------------------------------


def test_base_pose_and_write_joints_round_trip(mixamo):
    bones = random_rotations(mixamo.bone_count, seed=3)
    base = mixamo.base_pose(bones)
    assert base.shape == (7, 4) and base.dtype == np.float32
    # Writing the base pose back as the joints gives the bones as they were.
    written = bones.copy()
    written[mixamo.chain_bones] = [0, 0, 0, 1]  # the chain bones are rewritten...
    with pytest.raises(AssertionError):
        assert same_rotations(written, bones)
    restored = rest(mixamo.bone_count)
    restored[:] = bones
    assert mixamo.write_joints(base, restored) is restored
    assert same_rotations(restored, bones)
    # ... and from any other start for the chain bones, the others left alone.
    assert mixamo.write_joints(base, written) is written
    assert same_rotations(written, bones)
    # out= is written in place and returned; sequences of numbers are taken.
    out = np.zeros((7, 4), np.float32)
    assert mixamo.base_pose(bones.tolist(), out=out) is out
    assert same_rotations(out, base)
    # The rest pose of a skeleton whose axes are the crowd's: identity everywhere.
    assert same_rotations(mixamo.base_pose(rest(mixamo.bone_count)), rest(7))


def drive(rig, crowd, character, animated, frames=60):
    """Runs the frame loop: the animated bone rotations become the base pose, the crowd
    steps, its joints come back as bone rotations (returned)."""
    posed = animated.copy()
    states = cg.entity_states([character], flags=0)
    states["position"][0] = [0, 0, 0]
    row = crowd.row_of(character)
    for frame in range(1, frames + 1):
        posed[:] = animated
        crowd.set_base_pose(character, rig.base_pose(posed))
        crowd.push_frame(frame / 30, states)
        crowd.step(1 / 30)
        rig.write_joints(crowd.read_joints(row, 1), posed)
    return posed


def test_a_crowd_turns_the_head_of_a_rigged_character_to_a_target():
    names, parents, translations = skeleton(MIXAMO)
    crowd = cg.Crowd(max_characters=2, units_per_metre=100)  # Y up, +Z forward, cm
    rig = cg.Rig(names, parents, translations, units_per_metre=100, crowd=crowd)
    character = crowd.add_character((0, 0, 0), chain=rig.chain)
    target = np.array([150.0, 165.0, 150.0])  # ahead, to the character's left (+X)
    crowd.set_gaze_target(character, point=target)
    head = names.index("mixamorig:Head")

    def head_angle(locals_):
        rotations, positions = forward_kinematics(locals_, parents, translations)
        return angle_between(rotate(rotations[head], [0, 0, 1]), target - positions[head])

    animated = rest(len(names))
    before = head_angle(animated)
    posed = drive(rig, crowd, character, animated)
    after = head_angle(posed)
    assert before > 40 and after < before - 20, (before, after)
    # Only the chain's bones moved.
    others = np.setdiff1d(np.arange(len(names)), rig.chain_bones)
    assert np.array_equal(posed[others], animated[others])


def test_a_rig_turns_its_axes_and_units_into_the_crowds():
    """An Unreal skeleton (Z up, +Y, cm) in a crowd of Y up, +Z, metres."""
    names, parents, translations = skeleton(UE5)
    crowd = cg.Crowd(max_characters=1)
    rig = cg.Rig(names, parents, translations, units_per_metre=100, crowd=crowd.config)
    character = crowd.add_character((0, 0, 0), chain=rig.chain)
    # Crowd (x, y, z) from skeleton (x, y, z): up Z -> Y, forward Y -> Z, left -X -> +X.
    skeleton_to_crowd = np.array([[-1, 0, 0], [0, 0, 1], [0, 1, 0]], dtype=np.float64)
    target = np.array([-1.5, 1.65, 1.5])  # metres: ahead, to the character's right
    crowd.set_gaze_target(character, point=target)
    head = names.index("head")

    def head_angle(locals_):
        rotations, positions = forward_kinematics(locals_, parents, translations)
        forward = skeleton_to_crowd @ rotate(rotations[head], [0, 1, 0])
        return angle_between(forward, target - skeleton_to_crowd @ positions[head] / 100)

    animated = rest(len(names))
    before = head_angle(animated)
    after = head_angle(drive(rig, crowd, character, animated))
    assert before > 40 and after < before - 20, (before, after)


def test_const_calls_run_on_several_threads(mixamo):
    bones = random_rotations(mixamo.bone_count, seed=5)
    expected = mixamo.base_pose(bones)
    failures = []

    def work():
        for _ in range(200):
            if not np.array_equal(mixamo.base_pose(bones), expected):
                failures.append("differs")

    threads = [threading.Thread(target=work) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not failures


# --- hostile callers ----------------------------------------------------------------------


def test_hostile_skeletons_raise_the_right_errors():
    names, parents, translations = skeleton(MIXAMO)
    count = len(names)
    units = {"units_per_metre": 100}

    def rig(**changes):
        arguments = {"names": names, "parents": parents, "translations": translations,
                     **units, **changes}
        return cg.Rig(**arguments)

    nan = translations.copy()
    nan[3, 1] = np.nan
    duplicate = list(names)
    duplicate[9] = names[3]
    with_nul = list(names)
    with_nul[3] = "mixamorig:Spine2\0x"
    surrogate = list(names)
    surrogate[4] = "Neck\udc80"
    cases = [
        # (changes, class, built-in, text in the message)
        ({"names": "mixamorig:Hips"}, cg.ArgumentTypeError, TypeError, "names"),
        ({"names": [b"Hips"] + names[1:]}, cg.ArgumentTypeError, TypeError, "names[0]"),
        ({"names": 5}, cg.ArgumentTypeError, TypeError, "names"),
        ({"names": []}, cg.InvalidArgumentError, ValueError, "names"),
        ({"names": with_nul}, cg.InvalidArgumentError, ValueError, "names[3]"),
        ({"names": surrogate}, cg.InvalidArgumentError, ValueError, "names[4]"),
        ({"names": duplicate}, cg.InvalidArgumentError, ValueError, "unique"),
        ({"names": names[:-1] + [""]}, cg.InvalidArgumentError, ValueError, "empty"),
        ({"parents": parents[:-1]}, cg.InvalidArgumentError, ValueError, "parents"),
        ({"parents": [True] + parents[1:]}, cg.ArgumentTypeError, TypeError, "parents[0]"),
        ({"parents": [None, 0.0] + parents[2:]}, cg.ArgumentTypeError, TypeError, "parents[1]"),
        ({"parents": np.zeros(count)}, cg.ArgumentTypeError, TypeError, "parents"),
        ({"parents": [None, count] + parents[2:]}, cg.ArgumentRangeError, OverflowError,
         "parents[1]"),
        ({"parents": [None, -2] + parents[2:]}, cg.ArgumentRangeError, ValueError,
         "parents[1]"),
        ({"parents": [5] + parents[1:]}, cg.InvalidArgumentError, ValueError, "parents[0]"),
        ({"parents": "0123"}, cg.ArgumentTypeError, TypeError, "parents"),
        ({"translations": translations[:, :2]}, cg.InvalidArgumentError, ValueError,
         "translations"),
        ({"translations": translations[:-1]}, cg.InvalidArgumentError, ValueError,
         "translations"),
        ({"translations": "far"}, cg.ArgumentTypeError, TypeError, "translations"),
        ({"translations": nan}, cg.NonFiniteError, ValueError, "rest_translations[3]"),
        ({"rotations": rest(count - 1)}, cg.InvalidArgumentError, ValueError, "rotations"),
        ({"rotations": np.zeros((count, 4))}, cg.InvalidArgumentError, ValueError,
         "rest_rotations[0]"),
        ({"units_per_metre": "cm"}, cg.ArgumentTypeError, TypeError, "units_per_metre"),
        ({"units_per_metre": -1.0}, cg.InvalidArgumentError, ValueError, "units_per_metre"),
        ({"units_per_metre": float("nan")}, cg.NonFiniteError, ValueError, "units_per_metre"),
        ({"up": 6}, cg.ArgumentRangeError, ValueError, "up"),
        ({"up": -1}, cg.ArgumentRangeError, OverflowError, "up"),
        ({"forward": "+z"}, cg.ArgumentTypeError, TypeError, "forward"),
        ({"up": cg.Axis.POSITIVE_Y, "forward": cg.Axis.NEGATIVE_Y}, cg.InvalidArgumentError,
         ValueError, "perpendicular"),
        ({"bone_map": "Skull"}, cg.InvalidArgumentError, ValueError, "NAME=ROLE"),
        ({"bone_map": "mixamorig:Head=brain"}, cg.InvalidArgumentError, ValueError, "brain"),
        ({"bone_map": "Nobody=head"}, cg.InvalidArgumentError, ValueError, "Nobody"),
        ({"bone_map": "Head=head\0"}, cg.InvalidArgumentError, ValueError, "bone_map"),
        ({"bone_map": {"Head": 9}}, cg.ArgumentRangeError, ValueError, "bone_map"),
        ({"bone_map": {"Head": 2.0}}, cg.ArgumentTypeError, TypeError, "bone_map"),
        ({"bone_map": {"A,B": "head"}}, cg.InvalidArgumentError, ValueError, "bone_map"),
        ({"bone_map": {"Head": "head=x"}}, cg.InvalidArgumentError, ValueError, "bone_map"),
        ({"bone_map": {5: "head"}}, cg.ArgumentTypeError, TypeError, "bone_map"),
        ({"bone_map": ["Head=head"]}, cg.ArgumentTypeError, TypeError, "bone_map"),
        ({"crowd": "the crowd"}, cg.ArgumentTypeError, TypeError, "crowd"),
        ({"translations": translations * 1e6}, cg.InvalidArgumentError, ValueError,
         "units_per_metre"),
    ]
    for changes, cls, builtin, text in cases:
        with pytest.raises(cg.Error) as info:
            rig(**changes)
        error = info.value
        assert isinstance(error, cls) and isinstance(error, builtin), (changes, error)
        assert text in str(error), (changes, error)
    with pytest.raises(cg.ArgumentRangeError):
        cg.Rig([f"b{i}" for i in range(cg.CG_MAX_RIG_BONES + 1)], [], [])
    with pytest.raises(cg.InvalidArgumentError, match="rotations"):
        cg.Rig(names, parents, translations, 100)  # units_per_metre is keyword-only
    # A crowd's config may be given instead of the crowd.
    assert rig(crowd=cg.crowd_config(units_per_metre=100)).joint_count == 7


def test_hostile_frames_raise_and_write_nothing(mixamo):
    count = mixamo.bone_count
    bones = random_rotations(count, seed=8)
    joints = mixamo.base_pose(bones)
    nan = bones.copy()
    nan[2, 0] = np.nan
    zero = bones.copy()
    zero[2] = 0
    out = np.full((7, 4), 7, np.float32)
    cases = [
        (lambda: mixamo.base_pose(bones[:-1]), cg.InvalidArgumentError, "bone_rotations"),
        (lambda: mixamo.base_pose(bones[:, :3]), cg.InvalidArgumentError, "bone_rotations"),
        (lambda: mixamo.base_pose("bones"), cg.ArgumentTypeError, "bone_rotations"),
        (lambda: mixamo.base_pose(nan, out=out), cg.NonFiniteError, "bone_rotations[2]"),
        (lambda: mixamo.base_pose(zero, out=out), cg.InvalidArgumentError, "bone_rotations[2]"),
        (lambda: mixamo.base_pose(bones, out=np.zeros((7, 4))), cg.ArgumentTypeError, "out"),
        (lambda: mixamo.base_pose(bones, out=np.zeros((8, 4), np.float32)),
         cg.InvalidArgumentError, "out"),
        (lambda: mixamo.base_pose(bones, out=np.zeros((7, 4), np.float32)[::-1]),
         cg.InvalidArgumentError, "out"),
        (lambda: mixamo.base_pose(bones, out=[[0.0] * 4] * 7), cg.ArgumentTypeError, "out"),
    ]
    written = bones.copy()
    nan_joints = joints.copy()
    nan_joints[6, 3] = np.inf
    read_only = bones.copy()
    read_only.flags.writeable = False
    cases += [
        (lambda: mixamo.write_joints(joints[:-1], written), cg.InvalidArgumentError, "joints"),
        (lambda: mixamo.write_joints(nan_joints, written), cg.NonFiniteError, "joints[6]"),
        (lambda: mixamo.write_joints(joints, bones.tolist()), cg.ArgumentTypeError,
         "bone_rotations"),
        (lambda: mixamo.write_joints(joints, bones.astype(np.float64)), cg.ArgumentTypeError,
         "bone_rotations"),
        (lambda: mixamo.write_joints(joints, read_only), cg.InvalidArgumentError,
         "bone_rotations"),
        (lambda: mixamo.write_joints(joints, written[:-1]), cg.InvalidArgumentError,
         "bone_rotations"),
        (lambda: mixamo.write_joints(joints, np.ascontiguousarray(written.T).T),
         cg.InvalidArgumentError, "bone_rotations"),
        (lambda: mixamo.write_joints(written[:7], written), cg.InvalidArgumentError, "overlaps"),
        (lambda: mixamo.base_pose(written, out=written[:7]), cg.InvalidArgumentError,
         "overlaps"),
    ]
    for call, cls, text in cases:
        with pytest.raises(cg.Error) as info:
            call()
        assert isinstance(info.value, cls), (text, info.value)
        assert text in str(info.value), info.value
    assert np.all(out == 7), "out was written by a failed call"
    assert np.array_equal(written, bones), "bone_rotations were written by a failed call"


def test_a_closed_rig_refuses_every_call():
    names, parents, translations = skeleton(MIXAMO)
    rig = cg.Rig(names, parents, translations, units_per_metre=100)
    bones = rest(len(names))
    rig.close()
    rig.close()  # twice is fine
    assert rig.closed and repr(rig) == "<crowdgaze.Rig: closed>"
    calls = [
        lambda: rig.chain, lambda: rig.bone_count, lambda: rig.joint_count,
        lambda: rig.chain_bones, lambda: rig.roles, lambda: rig.report,
        lambda: rig.base_pose(bones), lambda: rig.write_joints(rest(7), bones),
        lambda: rig.handle,
    ]
    for call in calls:
        with pytest.raises(cg.ClosedError) as info:
            call()
        assert isinstance(info.value, ValueError)
    with cg.Rig(names, parents, translations, units_per_metre=100) as again:
        assert again.joint_count == 7
    assert again.closed
    with pytest.raises(RuntimeError):
        again.__init__(names, parents, translations)
    for refused in (copy.copy, copy.deepcopy, pickle.dumps):
        with pytest.raises(TypeError):
            refused(again)


def test_closing_a_rig_under_calls_in_child_processes():
    """Crash-prone: each in a child process (see test_hostile.py). An argument whose
    conversion closes the rig makes the call raise (closed) instead of using a freed rig;
    close() from another thread waits for the base poses in flight on four threads."""
    skeleton_code = f"""
        names = {[name for name, _, _ in MIXAMO]!r}
        parents = {[None if p is None else [n for n, _, _ in MIXAMO].index(p)
                    for _, p, _ in MIXAMO]!r}
        offsets = {[list(offset) for _, _, offset in MIXAMO]!r}
        rig = cg.Rig(names, parents, offsets, units_per_metre=100)
        bones = np.tile(np.float32([0, 0, 0, 1]), (len(names), 1))
        """
    result = run_alone(
        skeleton_code
        + """
        class Closer:
            def __float__(self):
                rig.close()
                return 1.0
        outcomes = []
        for call in (lambda: rig.base_pose([[0, 0, 0, Closer()]] + [[0, 0, 0, 1]] * 22),
                     lambda: rig.write_joints([[0, 0, 0, 1]] * 7, bones)):
            try:
                call()
                outcomes.append(["ok", ""])
            except Exception as error:
                outcomes.append([outcome(error), str(error)])
        del rig
        gc.collect()
        print(json.dumps({"outcomes": outcomes}))
        """
    )
    for result_outcome, message in result["outcomes"]:
        assert result_outcome == "ValueError" and "closed" in message, result
    result = run_alone(
        textwrap.dedent(skeleton_code)
        + textwrap.dedent(
            """
            outs = [np.zeros((7, 4), np.float32) for _ in range(4)]
            OBJ, DELAY, CLOSERS = rig, 0.02, 2
            CALLS = [lambda o=o: rig.base_pose(bones, out=o) for o in outs]
            """
        )
        + CONCURRENT_CLOSE
    )
    check_concurrent_close(result)


# --- the documentation ----------------------------------------------------------------------


def test_the_readmes_python_blocks_run(capsys):
    """Every ``python`` block of ``bindings/python/README.md`` (its "Your own skeleton"
    snippet among them) runs as it is."""
    text = (REPOSITORY / "bindings" / "python" / "README.md").read_text()
    blocks = [block.split("```", 1)[0] for block in text.split("```python\n")[1:]]
    assert any("cg.Rig(" in block for block in blocks)
    for block in blocks:
        exec(compile(block, "bindings/python/README.md", "exec"), {})
    assert "gaze chain of 3 joints" in capsys.readouterr().out
