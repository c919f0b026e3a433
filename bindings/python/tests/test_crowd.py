"""A real crowd through the Python binding: walkers and bystanders pushed frame by frame,
stepped, and their gaze, joints, eyes and eyelids read back and checked against geometry."""

import ctypes

import numpy as np
import pytest

import crowdgaze as cg

EYE_HEIGHT = 1.62  # the human chain's eyes above the character's position (metres)
FPS = 30


def quat_multiply(a, b):
    """Hamilton product of (..., 4) x y z w arrays."""
    ax, ay, az, aw = np.moveaxis(np.asarray(a, np.float64), -1, 0)
    bx, by, bz, bw = np.moveaxis(np.asarray(b, np.float64), -1, 0)
    return np.stack(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ],
        axis=-1,
    )


def yaw_degrees(q):
    """Yaw (counter-clockwise about +Y from +Z) of +Z rotated by q."""
    x, y, z, w = q
    return np.degrees(np.arctan2(2 * (x * z + w * y), 1 - 2 * (x * x + y * y)))


def angle_degrees(u, v):
    u, v = np.asarray(u, np.float64), np.asarray(v, np.float64)
    cosine = u @ v / (np.linalg.norm(u) * np.linalg.norm(v))
    return np.degrees(np.arccos(np.clip(cosine, -1, 1)))


START = np.array([[-1, 0, -8], [1, 0, 8], [-3, 0, 0], [3, 0, 0]], np.float32)
VELOCITY = np.array([[0, 0, 1.4], [0, 0, -1.4], [0, 0, 0], [0, 0, 0]], np.float32)
HEADINGS = [0.0, np.pi, 0.0, 0.0]  # walker 1 walks along -Z


def street(seed=3):
    """Two walkers passing each other between two bystanders and a lamp (3 m high)."""
    crowd = cg.Crowd(max_characters=4, max_objects=1, seed=seed)
    ids = [crowd.add_character(p, heading) for p, heading in zip(START, HEADINGS)]
    lamp = crowd.add_object((0, 0, 0), look_at_height=3.0)
    return crowd, ids, lamp


def run_street(crowd, ids, seconds, on_frame=None):
    states = cg.entity_states(ids, START)
    for frame in range(1, int(seconds * FPS) + 1):
        t = frame / FPS
        states["position"] = START + VELOCITY * t
        crowd.push_frame(t, states)
        crowd.step(1 / FPS)
        if on_frame:
            on_frame(t, states)


def test_walkers_look_at_real_targets():
    crowd, ids, lamp = street()
    assert ids == [0, 1, 2, 3] and len(crowd) == 4
    seen = set()
    frames_checked = 0

    def check(t, states):
        nonlocal frames_checked
        gaze = crowd.read_gaze()
        assert gaze.dtype == cg.GAZE_INFO_DTYPE and gaze.shape == (4,)
        assert list(gaze["character"]) == ids
        positions = {int(i): states["position"][k] for k, i in enumerate(ids)}
        for row, me in zip(gaze, ids):
            assert 0.0 <= row["attentive_fraction"] <= 1.0
            if row["attending"]:
                target = int(row["target"])
                assert target != me and (target in ids or target == lamp)
                seen.add((me, target))
                expected = (
                    np.array([0, 3.0, 0])
                    if target == lamp
                    else positions[target] + [0, EYE_HEIGHT, 0]
                )
                np.testing.assert_allclose(row["target_position"], expected, atol=1e-4)
            else:
                assert row["target"] == cg.NO_TARGET
                # Looking ahead: 10 m straight ahead at eye height; walker 1 walks along -Z,
                # the others face +Z (heading 0, or walking along +Z).
                forward = -1 if VELOCITY[ids.index(me), 2] < 0 else 1
                ahead = positions[me] + [0, EYE_HEIGHT, 10 * forward]
                np.testing.assert_allclose(row["target_position"], ahead, atol=1e-4)
        frames_checked += 1

    run_street(crowd, ids, 10, check)
    assert frames_checked == 300
    # Both walkers found something to look at; the lamp and a bystander among the targets.
    assert {me for me, _ in seen} >= {0, 1}
    assert any(target == lamp for _, target in seen)
    assert any(target in (2, 3) for me, target in seen if me in (0, 1))
    gaze = crowd.read_gaze()
    assert gaze["interest_count"][:2].min() >= 1


def test_a_character_turns_to_a_point_eyes_first():
    crowd, ids, _ = street()
    watcher = ids[2]
    # 60 degrees to the watcher's left (Y up, +Z forward: left is +X), at eye height.
    point = START[2] + [3 * np.sin(np.radians(60)), 1.6, 3 * np.cos(np.radians(60))]
    crowd.set_gaze_target(watcher, point=point)
    base = np.tile(np.array([0, 0, 0, 1], np.float32), (10, 1))
    base[0] = [np.sin(np.radians(5)), 0, 0, np.cos(np.radians(5))]  # spine bent 10 degrees
    crowd.set_base_pose(watcher, base)
    eye_yaw_at = {}

    def record(t, states):
        joints = crowd.read_joints(2, 1)
        world = np.array([0, 0, 0, 1.0])
        for j in joints[:8]:
            world = quat_multiply(world, j)
        head = yaw_degrees(world)
        eyes = (
            yaw_degrees(quat_multiply(world, joints[8]))
            + yaw_degrees(quat_multiply(world, joints[9]))
        ) / 2
        eye_yaw_at[round(t * FPS)] = (eyes, head)

    run_street(crowd, ids, 3, record)
    # Eyes lead: early on the eyes have turned more than the head.
    eyes_early, head_early = eye_yaw_at[6]
    assert eyes_early > head_early + 10
    eyes, head = eye_yaw_at[90]
    assert 20 < head < eyes
    # The eyes look exactly at the point.
    info = crowd.read_eyes(2, 1)[0]
    assert info["character"] == watcher
    for origin, direction in [
        ("left_origin", "left_direction"),
        ("right_origin", "right_direction"),
    ]:
        assert angle_degrees(info[direction], point - info[origin]) < 1.0
        assert abs(np.linalg.norm(info[direction]) - 1) < 1e-5
    # Final rotations are base * delta, and unit.
    joints, deltas = crowd.read_joints(2, 1), crowd.read_joint_deltas(2, 1)
    np.testing.assert_allclose(quat_multiply(base, deltas), joints, atol=2e-6)
    np.testing.assert_allclose(np.linalg.norm(joints, axis=1), 1, atol=1e-5)
    # Cleared: the watcher returns to its base pose over its deactivation time.
    crowd.clear_gaze_target(watcher)
    run_street(crowd, ids, 0)  # nothing pushed
    for _ in range(3 * FPS):
        crowd.step(1 / FPS)
    np.testing.assert_allclose(np.abs(crowd.read_joint_deltas(2, 1)[:, 3]), 1, atol=1e-3)


def test_same_seed_same_bits():
    results = []
    for _ in range(2):
        crowd, ids, _ = street(seed=11)
        run_street(crowd, ids, 4)
        results.append((crowd.read_joints(), crowd.read_gaze(), crowd.read_eyes()))
    for a, b in zip(*results):
        assert a.tobytes() == b.tobytes()
    crowd, ids, _ = street(seed=12)
    run_street(crowd, ids, 4)
    assert crowd.read_gaze().tobytes() != results[0][1].tobytes()


def test_ranged_steps_from_python_threads_match_one_call_steps():
    import threading

    one_call, ids, _ = street(seed=5)
    run_street(one_call, ids, 3)
    pooled = cg.Crowd(max_characters=4, max_objects=1, seed=5, threads=2)
    assert [pooled.add_character(p, h) for p, h in zip(START, HEADINGS)] == ids
    pooled.add_object((0, 0, 0), look_at_height=3.0)
    run_street(pooled, ids, 3)
    ranged, ids, _ = street(seed=5)
    states = cg.entity_states(ids, START)
    for frame in range(1, 3 * FPS + 1):
        t = frame / FPS
        states["position"] = START + VELOCITY * t
        ranged.push_frame(t, states)
        ranged.begin_step(1 / FPS)
        workers = [threading.Thread(target=ranged.step_range, args=(i, 1)) for i in (0, 2, 3)]
        for worker in workers:
            worker.start()
        for worker in workers:
            worker.join()
        ranged.end_step()  # steps character 1, which no range covered
    for crowd in (pooled, ranged):
        assert crowd.read_joints().tobytes() == one_call.read_joints().tobytes()
        assert crowd.read_gaze().tobytes() == one_call.read_gaze().tobytes()
    with pytest.raises(cg.Error):
        ranged.step_range(0, 1)  # no step open


def test_ranged_pushes_from_python_threads_match_one_push():
    import threading

    one_push, ids, _ = street(seed=5)
    run_street(one_push, ids, 3)
    ranged, ids, _ = street(seed=5)
    states = cg.entity_states(ids, START)
    for frame in range(1, 3 * FPS + 1):
        t = frame / FPS
        states["position"] = START + VELOCITY * t
        ranged.begin_push(t)
        with pytest.raises(cg.Error):
            ranged.step(1 / FPS)  # a push is open
        parts = [states[0:1], states[1:3], states[3:]]
        # A part is a view of the frame's array, passed without a copy.
        _keep, pointer, _ = cg._arrays.records_in(parts[1], cg.EntityState, "test", "states")
        assert ctypes.cast(pointer, ctypes.c_void_p).value == states[1:].ctypes.data
        workers = [threading.Thread(target=ranged.push_range, args=(part,)) for part in parts]
        for worker in workers:
            worker.start()
        for worker in workers:
            worker.join()
        with pytest.raises(cg.Error):
            ranged.push_range(states[2:3])  # pushed already in this push
        ranged.end_push()
        ranged.step(1 / FPS)
    assert ranged.read_joints().tobytes() == one_push.read_joints().tobytes()
    assert ranged.read_gaze().tobytes() == one_push.read_gaze().tobytes()
    with pytest.raises(cg.Error):
        ranged.push_range(states)  # no push open
    with pytest.raises(cg.Error):
        ranged.end_push()


def test_numpy_arrays_pass_without_copies():
    crowd, ids, _ = street()
    states = cg.entity_states(ids, START)
    keep, pointer, count = cg._arrays.records_in(states, cg.EntityState, "test", "states")
    assert keep.ctypes.data == states.ctypes.data and count == 4
    assert ctypes.cast(pointer, ctypes.c_void_p).value == states.ctypes.data
    crowd.push_frame(0.0, states)
    crowd.step(0.0)

    quats = np.tile(np.array([0, 0, 0, 1], np.float32), (10, 1))
    rows = cg._arrays.float_rows(quats, cg.Quat, "test", "local")
    assert rows.ctypes.data == quats.ctypes.data  # (n, 4) float32 C-contiguous: no copy
    copied = cg._arrays.float_rows(quats.astype(np.float64), cg.Quat, "test", "local")
    assert not np.shares_memory(copied, quats) and copied.dtype == np.float32
    strided = np.tile(np.array([0, 0, 0, 1, 9], np.float32), (10, 1))[:, :4]
    assert not np.shares_memory(cg._arrays.float_rows(strided, cg.Quat, "test", "x"), strided)
    crowd.set_base_pose(ids[0], quats)
    crowd.set_base_pose(ids[1], quats.astype(np.float64).tolist())  # a list works too
    crowd.set_base_poses(ids[2:], np.concatenate([quats, strided]))

    # Outputs: written in place.
    out = np.zeros((40, 4), np.float32)
    assert crowd.read_joints(out=out) is out
    np.testing.assert_array_equal(out, crowd.read_joints())
    # An out= of another dtype, layout or shape is refused: results are never converted.
    with pytest.raises(TypeError, match="out must have the dtype float32"):
        crowd.read_joints(out=np.zeros((40, 4), np.float64))
    with pytest.raises(ValueError, match="out must be C-contiguous"):
        crowd.read_joints(out=np.zeros((4, 40), np.float32).T)
    gaze = np.zeros(4, cg.GAZE_INFO_DTYPE)
    assert crowd.read_gaze(out=gaze) is gaze
    assert list(gaze["character"]) == ids
    with pytest.raises(ValueError, match="out must have the shape"):
        crowd.read_gaze(out=np.zeros(5, cg.GAZE_INFO_DTYPE))  # never truncated or padded
    with pytest.raises(ValueError):
        crowd.read_joints(out=np.zeros((39, 4), np.float32))

    # A ctypes array of EntityState and a list of them work too.
    array = (cg.EntityState * 2)()
    for k in range(2):
        array[k].struct_size = ctypes.sizeof(cg.EntityState)
        cg.lib.cg_entity_state_init(ctypes.byref(array[k]))
        array[k].id = ids[k]
        array[k].position = cg.Vec3(*START[k])
    crowd.push_frame(0.1, array)
    crowd.push_frame(0.2, list(array))


def test_offline_plan_and_constraints():
    crowd = cg.Crowd(max_characters=2, max_objects=0, max_recorded_states=600)
    a = crowd.add_character((-0.8, 0, -8))
    b = crowd.add_character((0.8, 0, 8), heading=np.pi)
    for me in (a, b):
        crowd.set_character_params(me, attention_fraction=0.6)
        assert abs(crowd.character_params(me).attention_fraction - 0.6) < 1e-6
    states = cg.entity_states([a, b])
    for frame in range(300):
        t = frame / FPS
        states["position"] = [[-0.8, 0, -8 + 1.6 * t], [0.8, 0, 8 - 1.6 * t]]
        crowd.push_frame(t, states)
    crowd.plan()
    total = 0
    for me, other in ((a, b), (b, a)):
        constraints = crowd.read_constraints(me)
        assert constraints.dtype == cg.CONSTRAINT_DTYPE
        for c in constraints:
            assert c["entity"] == other
            assert 0 <= c["begin"] < c["end"] <= 10
            assert c["s_max"] > 0
        total += constraints.size
    assert total >= 1
    with pytest.raises(cg.Error) as error:
        crowd.push_frame(10.0, states)
    assert error.value.status == cg.Status.WRONG_STATE
    crowd.step(1 / FPS)
    crowd.clear_plan()
    crowd.push_frame(10.0, states)


def test_score_and_entities():
    crowd, ids, lamp = street()
    score = crowd.score(ids[2], lamp)
    assert score.distance == pytest.approx(3.0, abs=1e-5)
    assert score.pruned in (0, 1)
    assert 0 <= score.total <= 1
    crowd.set_impact(lamp, 2.0)
    crowd.remove_entity(ids[0])
    assert len(crowd) == 3
    # The last character moved into the removed one's place.
    assert list(crowd.read_gaze()["character"]) == [ids[3], ids[1], ids[2]]
    assert crowd.joint_total() == 30
    config = crowd.config
    assert config.max_characters == 4 and config.seed == 3
    assert config.struct_size == ctypes.sizeof(cg.CrowdConfig)
    with cg.Crowd(crowd_config := cg.crowd_config(max_characters=1)) as small:
        assert small.config.max_characters == 1 and crowd_config.max_characters == 1
    with pytest.raises(ValueError):
        small.step(0.1)


def test_characters_look_at_the_viewer():
    crowd = cg.Crowd(max_characters=2, max_objects=0, seed=1)
    me = crowd.add_character((0, 0, 0))
    viewer = crowd.set_viewer((0.3, 1.7, 2.0), impact=3.0)
    assert viewer != me
    for _ in range(3 * FPS):
        crowd.step(1 / FPS)
    gaze = crowd.read_gaze()[0]
    assert (gaze["target"], gaze["head_target"], gaze["attending"]) == (viewer, viewer, 1)
    np.testing.assert_allclose(gaze["target_position"], [0.3, 1.7, 2.0], atol=1e-5)
    # Moved: the same entity, looked at where it now is.
    assert crowd.set_viewer((-0.3, 1.7, 2.0), impact=3.0) == viewer
    crowd.step(1 / FPS)
    np.testing.assert_allclose(crowd.read_gaze()[0]["target_position"], [-0.3, 1.7, 2.0], atol=1e-5)
    for _ in range(FPS):
        crowd.step(1 / FPS)
    eyes = crowd.read_eyes()[0]
    target = np.array([-0.3, 1.7, 2.0])
    assert angle_degrees(eyes["left_direction"], target - eyes["left_origin"]) < 1.0
    crowd.remove_entity(viewer)
    crowd.step(1 / FPS)
    assert crowd.read_gaze()[0]["target"] != viewer


def test_attention_models_and_periods():
    crowd = cg.Crowd(max_characters=3, max_objects=2, seed=4)
    models = [cg.AttentionModel.CROWD, cg.AttentionModel.SALIENCY, cg.AttentionModel.BASELINE]
    ids = [
        crowd.add_character((2.0 * k, 0, 0), attention_model=model)
        for k, model in enumerate(models)
    ]
    for k, model in enumerate(models):
        assert crowd.character_params(ids[k]).attention_model == model
    crowd.set_character_params(ids[0], attention_model=cg.AttentionModel.SALIENCY)
    assert crowd.character_params(ids[0]).attention_model == cg.AttentionModel.SALIENCY
    crowd.add_object((1, 0, 3), look_at_height=1.5)
    crowd.set_attention_period(ids[2], 4)
    with pytest.raises(cg.Error) as error:
        crowd.set_attention_period(ids[2], 65)
    assert error.value.status == cg.Status.INVALID_ARGUMENT
    for _ in range(2 * FPS):
        crowd.step(1 / FPS)
    gaze = crowd.read_gaze()
    assert set(gaze["target_part"]) <= {int(p) for p in cg.TargetPart}
    assert np.all(np.isfinite(crowd.read_joints()))


def blinking_crowd(**fields):
    """Three bystanders facing different ways (no objects), created with ``fields``."""
    crowd = cg.Crowd(max_characters=3, max_objects=0, seed=9, **fields)
    ids = [crowd.add_character((2.0 * k, 0, 0), heading=k * np.pi / 3) for k in range(3)]
    return crowd, ids


def test_read_eyelids_gives_one_record_per_character_and_blinks():
    crowd, ids = blinking_crowd()
    crowd.step(1 / FPS)
    lids = crowd.read_eyelids()
    assert lids.dtype == cg.EYELIDS_DTYPE and lids.shape == (3,)
    assert list(lids["character"]) == ids == list(crowd.read_gaze()["character"])
    assert list(crowd.read_eyelids(1)["character"]) == ids[1:]
    assert list(crowd.read_eyelids(2, 1)["character"]) == ids[2:]
    assert crowd.read_eyelids(3).shape == (0,)
    # 20 s at the default rate (17 blinks a minute each): closures stay in [0, 1], the lids
    # follow the eyes (finite pitches), and some blink closes the eyes more than half-way.
    out = np.zeros(3, cg.EYELIDS_DTYPE)
    most_closed = 0.0
    for _ in range(20 * FPS):
        crowd.step(1 / FPS)
        assert crowd.read_eyelids(out=out) is out
        for side in ("left", "right"):
            closure = out[f"{side}_closure"]
            assert np.all((closure >= 0) & (closure <= 1)), closure
            assert np.all(np.isfinite(out[f"{side}_lid_pitch"]))
        np.testing.assert_array_equal(out["left_closure"], out["right_closure"])
        most_closed = max(most_closed, float(out["left_closure"].max()))
    assert most_closed > 0.5
    assert list(out["character"]) == ids


def test_blinks_follow_the_config():
    config = cg.crowd_config(blink_rate=30, blink_rate_spread=0.2, lid_gain=0.5,
                             evoked_blink_min_amplitude=0.1, evoked_blink_full_amplitude=0.4,
                             evoked_blink_probability=0.5,
                             eye_motion=cg.EyeMotion.MAIN_SEQUENCE)
    crowd = cg.Crowd(config, max_characters=2)
    stored = crowd.config
    assert stored.blink_rate == 30 and stored.lid_gain == 0.5
    assert stored.blink_rate_spread == pytest.approx(0.2)
    assert stored.evoked_blink_min_amplitude == pytest.approx(0.1)
    assert stored.evoked_blink_full_amplitude == pytest.approx(0.4)
    assert stored.evoked_blink_probability == pytest.approx(0.5)
    assert stored.eye_motion == cg.EyeMotion.MAIN_SEQUENCE == cg.CG_EYE_MOTION_MAIN_SEQUENCE
    defaults = cg.crowd_config()
    assert defaults.blink_rate == 17 and defaults.eye_motion == cg.EyeMotion.PAPER
    assert defaults.evoked_blink_probability == pytest.approx(0.97)
    # No spontaneous and no gaze-evoked blinks: the lids never close, even as the gaze
    # turns to a point far to the side.
    crowd, ids = blinking_crowd(blink_rate=0, evoked_blink_probability=0)
    for frame in range(20 * FPS):
        if frame % (2 * FPS) == 0:
            side = 1 if frame % (4 * FPS) == 0 else -1
            crowd.set_gaze_target(ids[0], point=(6.0 * side, 1.6, 1.0))
        crowd.step(1 / FPS)
        lids = crowd.read_eyelids()
        assert not lids["left_closure"].any() and not lids["right_closure"].any()


@pytest.mark.parametrize(
    ("field", "value", "status"),
    [
        ("blink_rate", -1, cg.Status.INVALID_ARGUMENT),
        ("blink_rate", 121, cg.Status.INVALID_ARGUMENT),
        ("blink_rate_spread", 1, cg.Status.INVALID_ARGUMENT),
        ("evoked_blink_full_amplitude", 0.1, cg.Status.INVALID_ARGUMENT),
        ("evoked_blink_probability", 1.5, cg.Status.INVALID_ARGUMENT),
        ("lid_gain", 2.5, cg.Status.INVALID_ARGUMENT),
        ("eye_motion", 7, cg.Status.INVALID_ARGUMENT),
        ("blink_rate", float("nan"), cg.Status.NON_FINITE),
        ("lid_gain", float("inf"), cg.Status.NON_FINITE),
    ],
)
def test_bad_blink_settings_are_refused(field, value, status):
    with pytest.raises(cg.Error) as error:
        cg.Crowd(max_characters=1, **{field: value})
    assert error.value.status == status
    assert error.value.function == "cg_crowd_create"
    if status == cg.Status.INVALID_ARGUMENT:
        assert field in error.value.message


def test_read_eyelids_refuses_a_wrong_out_or_range():
    crowd, ids = blinking_crowd()
    crowd.step(1 / FPS)
    out = np.zeros(3, cg.EYELIDS_DTYPE)
    out["character"] = cg.NO_TARGET
    with pytest.raises(ValueError, match=r"out must have the shape \(3,\)"):
        crowd.read_eyelids(out=np.zeros(2, cg.EYELIDS_DTYPE))
    with pytest.raises(ValueError, match=r"out must have the shape \(1,\)"):
        crowd.read_eyelids(1, 1, out=out)
    with pytest.raises(TypeError, match="out must have the dtype crowdgaze.EYELIDS_DTYPE"):
        crowd.read_eyelids(out=np.zeros(3, cg.EYE_INFO_DTYPE))
    with pytest.raises(TypeError, match="out must be a numpy array"):
        crowd.read_eyelids(out=(cg.Eyelids * 3)())
    with pytest.raises(ValueError, match="out must be C-contiguous"):
        crowd.read_eyelids(out=np.zeros(6, cg.EYELIDS_DTYPE)[::2])
    with pytest.raises(cg.Error) as error:
        crowd.read_eyelids(2, 2)
    assert error.value.status == cg.Status.INVALID_ARGUMENT
    with pytest.raises(OverflowError, match="first"):
        crowd.read_eyelids(-1)
    assert (out["character"] == cg.NO_TARGET).all()  # nothing written by the failed calls
    # The C function itself refuses too small an output.
    lids = (cg.Eyelids * 2)()
    status = cg.lib.cg_crowd_read_eyelids(crowd.handle, 0, 3, lids, len(lids))
    assert status == cg.CG_STATUS_INVALID_ARGUMENT
    assert lids[0].character == 0


def test_conversations_are_formed_read_back_and_ended():
    crowd = cg.Crowd(max_characters=6, max_objects=1, max_conversations=2, seed=1)
    ids = [crowd.add_character((1.5 * k, 0, 0)) for k in range(6)]
    lamp = crowd.add_object((0, 0, 3))
    assert crowd.config.max_conversations == 2 and cg.CG_MAX_CONVERSATION_MEMBERS == 8
    pair = crowd.set_conversation(ids[:2])  # a list
    trio = crowd.set_conversation(np.array(ids[2:5], np.uint32))  # a uint32 array
    assert isinstance(pair, int) and pair != trio
    assert [crowd.conversation_of(i) for i in ids] == [pair, pair, trio, trio, trio, None]
    # A character is in one conversation at a time.
    with pytest.raises(cg.Error) as error:
        crowd.set_conversation((ids[5], ids[0]))
    assert error.value.status == cg.Status.INVALID_ARGUMENT
    assert "already in conversation" in error.value.message
    # Removing a member leaves the others talking; a group left with one member ends.
    crowd.remove_entity(ids[4])
    assert crowd.conversation_of(ids[2]) == trio
    crowd.remove_entity(ids[1])
    assert crowd.conversation_of(ids[0]) is None
    with pytest.raises(cg.Error) as error:
        crowd.remove_conversation(pair)
    assert error.value.status == cg.Status.NOT_FOUND
    assert error.value.function == "cg_crowd_remove_conversation"
    crowd.remove_conversation(trio)
    assert crowd.conversation_of(ids[2]) is None and crowd.conversation_of(ids[3]) is None
    with pytest.raises(cg.Error) as error:  # removing it twice
        crowd.remove_conversation(trio)
    assert error.value.status == cg.Status.NOT_FOUND
    # A new group takes the freed room; the ended groups' ids do not name it.
    again = crowd.set_conversation([ids[0], ids[5]])
    assert again not in (pair, trio)
    crowd.step(1 / FPS)
    with pytest.raises(cg.Error) as error:
        crowd.conversation_of(lamp)
    assert error.value.status == cg.Status.INVALID_ARGUMENT


def test_max_conversations_is_a_capacity():
    crowd = cg.Crowd(max_characters=4, max_conversations=1)
    ids = [crowd.add_character((k, 0, 0)) for k in range(4)]
    crowd.set_conversation(ids[:2])
    with pytest.raises(cg.Error) as error:
        crowd.set_conversation(ids[2:])
    assert error.value.status == cg.Status.CAPACITY
    assert "max_conversations" in error.value.message
    assert crowd.conversation_of(ids[2]) is None
    none_allowed = cg.Crowd(max_characters=2, max_conversations=0)
    a, b = none_allowed.add_character((0, 0, 0)), none_allowed.add_character((1, 0, 0))
    with pytest.raises(cg.Error) as error:
        none_allowed.set_conversation([a, b])
    assert error.value.status == cg.Status.CAPACITY


@pytest.mark.parametrize(
    ("members", "status", "words"),
    [
        (lambda ids, lamp: [ids[0]], cg.Status.INVALID_ARGUMENT, "not 1"),
        (lambda ids, lamp: [ids[0]] * 9, cg.Status.INVALID_ARGUMENT, "not 9"),
        (lambda ids, lamp: [ids[0], ids[1], ids[0]], cg.Status.INVALID_ARGUMENT, "twice"),
        (lambda ids, lamp: [ids[0], lamp], cg.Status.INVALID_ARGUMENT, "object"),
        (lambda ids, lamp: [ids[0], ids[2]], cg.Status.INVALID_ARGUMENT, "already"),
        (lambda ids, lamp: [ids[0], 12345], cg.Status.NOT_FOUND, "12345"),
    ],
    ids=["one member", "nine members", "a member twice", "an object", "already grouped",
         "an unknown id"],
)
def test_bad_conversations_are_refused_and_change_nothing(members, status, words):
    crowd = cg.Crowd(max_characters=4, max_objects=1, seed=2)
    ids = [crowd.add_character((k, 0, 0)) for k in range(4)]
    lamp = crowd.add_object((0, 0, 2))
    grouped = crowd.set_conversation(ids[2:])
    with pytest.raises(cg.Error) as error:
        crowd.set_conversation(members(ids, lamp))
    assert error.value.status == status
    assert error.value.function == "cg_crowd_set_conversation"
    assert words in error.value.message
    assert [crowd.conversation_of(i) for i in ids] == [None, None, grouped, grouped]


def test_conversation_arguments_are_checked_by_name():
    crowd = cg.Crowd(max_characters=2)
    ids = [crowd.add_character((k, 0, 0)) for k in range(2)]
    with pytest.raises(TypeError, match="Crowd.set_conversation: members"):
        crowd.set_conversation([ids[0], 1.5])
    with pytest.raises(OverflowError, match="Crowd.set_conversation: members"):
        crowd.set_conversation([ids[0], -1])
    with pytest.raises(TypeError, match="Crowd.set_conversation: members"):
        crowd.set_conversation(None)
    with pytest.raises(OverflowError, match="Crowd.remove_conversation: group"):
        crowd.remove_conversation(2**32)
    with pytest.raises(TypeError, match="Crowd.conversation_of: character"):
        crowd.conversation_of("0")
    assert crowd.conversation_of(ids[0]) is None


def test_the_talking_flag_decides_whom_the_listener_looks_at():
    # Three characters in a triangle, facing its centre, in one conversation: for 10 s the
    # first talks, then the second. The third, listening, looks at the one talking.
    crowd = cg.Crowd(max_characters=3, seed=4)
    positions = np.array([[0, 0, 0], [1.2, 0, 0], [0.6, 0, 1.0]], np.float32)
    centre = positions.mean(axis=0)
    headings = [float(np.arctan2(*(centre - p)[[0, 2]])) for p in positions]
    ids = [crowd.add_character(p, h) for p, h in zip(positions, headings)]
    crowd.set_conversation(ids)
    states = cg.entity_states(ids, positions, flags=0)
    states["heading"] = headings
    looks = np.zeros((2, 3))  # per talker, the frames the listener looks at each member
    for frame in range(20 * FPS):
        speaker = 0 if frame < 10 * FPS else 1
        states["flags"] = 0
        states["flags"][speaker] |= cg.CG_STATE_TALKING
        crowd.push_frame(frame / FPS, states)
        crowd.step(1 / FPS)
        target = crowd.read_gaze()["target"][2]
        if target in ids:
            looks[speaker, ids.index(target)] += 1
    share = looks / (10 * FPS)
    assert share[0, 0] > 0.4 and share[0, 1] < 0.05, share
    assert share[1, 1] > 0.4 and share[1, 0] < 0.05, share
    assert cg.STATE_TALKING == cg.CG_STATE_TALKING == 4


@pytest.mark.parametrize(
    ("field", "value", "status"),
    [
        ("max_conversations", 2**23 + 1, cg.Status.INVALID_ARGUMENT),
        ("talking_gain", -1, cg.Status.INVALID_ARGUMENT),
        ("eye_part_weight", 101, cg.Status.INVALID_ARGUMENT),
        ("listener_look_share", 1, cg.Status.INVALID_ARGUMENT),
        ("listener_glance_time", 0, cg.Status.INVALID_ARGUMENT),
        ("speaker_look_share", 0, cg.Status.INVALID_ARGUMENT),
        ("speaker_glance_time", 601, cg.Status.INVALID_ARGUMENT),
        ("idle_look_share", 1.5, cg.Status.INVALID_ARGUMENT),
        ("idle_glance_time", -1, cg.Status.INVALID_ARGUMENT),
        ("turn_start_aversion_time", 61, cg.Status.INVALID_ARGUMENT),
        ("listener_look_share", float("nan"), cg.Status.NON_FINITE),
        ("talking_gain", float("inf"), cg.Status.NON_FINITE),
    ],
)
def test_bad_conversation_settings_are_refused(field, value, status):
    with pytest.raises(cg.Error) as error:
        cg.Crowd(max_characters=1, **{field: value})
    assert error.value.status == status
    assert error.value.function == "cg_crowd_create"
    assert field in error.value.message


def test_conversation_settings_have_their_defaults_and_are_kept():
    defaults = cg.crowd_config()
    assert defaults.max_conversations == 64
    assert (defaults.talking_gain, defaults.eye_part_weight) == (1.5, 1.5)
    assert (defaults.listener_look_share, defaults.listener_glance_time) == (0.75, 6.0)
    assert defaults.speaker_look_share == pytest.approx(0.41)
    assert defaults.speaker_glance_time == pytest.approx(1.8)
    assert (defaults.idle_look_share, defaults.idle_glance_time) == (0.5, 2.5)
    assert defaults.turn_start_aversion_time == 1.0
    crowd = cg.Crowd(max_characters=1, max_conversations=3, talking_gain=2.0,
                     listener_look_share=0.5, turn_start_aversion_time=0.0)
    stored = crowd.config
    assert stored.max_conversations == 3 and stored.talking_gain == 2.0
    assert stored.listener_look_share == 0.5 and stored.turn_start_aversion_time == 0.0
