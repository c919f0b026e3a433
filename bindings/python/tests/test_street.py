"""The street model and gaze following through the Python binding: the preset, the
``street_*`` and ``follow_*`` settings (checked, refused with their names), and
``Crowd.read_following`` on a street where five people stare up at a window."""

import math

import numpy as np
import pytest

import crowdgaze as cg

FPS = 30
WINDOW = (0.0, 12.0, -6.0)
STARERS = 5
WALKERS = 30


def street(config: cg.CrowdConfig, units: float = 1.0):
    """A crowd of five starers (overriding targets at the window) and 30 passers-by with
    the street model, in `units` per metre; returns the crowd, the ids, the states and the
    walkers' speeds (units per second)."""
    crowd = cg.Crowd(config, max_characters=STARERS + WALKERS, seed=1969, units_per_metre=units)
    ids, positions, speeds = [], [], []
    for i in range(STARERS + WALKERS):
        if i < STARERS:
            position = (-1.0 + 0.5 * i, 0.0, 0.0)
            speed = 0.0
        else:
            k = i - STARERS
            position = (2.0 + k % 5, 0.0, -25.0 + (k * 37) % 50)
            speed = (1.0 if k % 2 else -1.0) * (1.1 + 0.05 * (k % 7))
        position = tuple(value * units for value in position)
        ids.append(crowd.add_character(position, math.pi if i < STARERS else 0.0,
                                       attention_model=cg.AttentionModel.STREET))
        positions.append(position)
        speeds.append(speed * units)
    for me in ids[:STARERS]:
        crowd.set_gaze_target(me, point=tuple(value * units for value in WINDOW))
    states = cg.entity_states(ids, positions, flags=cg.STATE_HEADING_FROM_MOTION)
    states["flags"][:STARERS] = 0
    return crowd, ids, states, np.array(speeds, np.float32)


def walk(crowd, states, speeds, frame: int, units: float = 1.0) -> None:
    """Moves the walkers on by a frame (turning back at +-25 m), pushes it and steps."""
    z = states["position"][:, 2]
    z += speeds / FPS
    speeds[np.abs(z) > 25.0 * units] *= -1
    crowd.push_frame(frame / FPS, states)
    crowd.step(1 / FPS)


def test_the_street_preset_and_its_defaults():
    config = cg.street_config()
    assert config.follow_enabled == 1 and config.max_distance == 17.0
    defaults = cg.crowd_config()
    assert defaults.follow_enabled == 0 and defaults.max_distance == 10.0
    assert defaults.street_view_half_angle == pytest.approx(math.radians(60))
    assert defaults.street_first_fixation_probability == pytest.approx(0.95)
    assert (defaults.street_latency_min, defaults.street_latency_max) == pytest.approx((0.55, 0.75))
    assert defaults.street_civil_distance == 3.0 and defaults.street_path_look_distance == 4.0
    assert defaults.follow_one_looker_probability == pytest.approx(0.42)
    assert defaults.follow_max_probability == pytest.approx(0.87)
    assert defaults.follow_distance == 10.0
    assert defaults.follow_view_half_angle == pytest.approx(math.pi / 2)
    assert (defaults.follow_glance_min, defaults.follow_glance_max) == (1.0, 2.5)
    # Fields are kept, and street_config takes fields as crowd_config does.
    gallup = cg.street_config(follow_one_looker_probability=0.12, follow_max_probability=0.3)
    with cg.Crowd(gallup, max_characters=2) as crowd:
        stored = crowd.config
        assert stored.follow_enabled == 1 and stored.max_distance == 17.0
        assert stored.follow_one_looker_probability == pytest.approx(0.12)
        assert stored.follow_max_probability == pytest.approx(0.3)
    assert cg.AttentionModel.STREET == cg.CG_ATTENTION_MODEL_STREET == 3


@pytest.mark.parametrize(
    ("field", "value", "status"),
    [
        ("street_view_half_angle", 4.0, cg.Status.INVALID_ARGUMENT),
        ("street_first_fixation_probability", 1.5, cg.Status.INVALID_ARGUMENT),
        ("street_latency_min", -1.0, cg.Status.INVALID_ARGUMENT),
        ("street_latency_max", 61.0, cg.Status.INVALID_ARGUMENT),
        ("street_fixation_median", 0.0, cg.Status.INVALID_ARGUMENT),
        ("street_fixation_log_spread", 3.0, cg.Status.INVALID_ARGUMENT),
        ("street_refixation_probability", -0.5, cg.Status.INVALID_ARGUMENT),
        ("street_refixation_gap_max", 601.0, cg.Status.INVALID_ARGUMENT),
        ("street_civil_distance", -1.0, cg.Status.INVALID_ARGUMENT),
        ("street_civil_look_probability", 2.0, cg.Status.INVALID_ARGUMENT),
        ("street_path_look_distance", 1001.0, cg.Status.INVALID_ARGUMENT),
        ("street_civil_look_distance", -1.0, cg.Status.INVALID_ARGUMENT),
        ("follow_enabled", 2, cg.Status.INVALID_ARGUMENT),
        ("follow_max_probability", 1.5, cg.Status.INVALID_ARGUMENT),
        ("follow_distance", -1.0, cg.Status.INVALID_ARGUMENT),
        ("follow_view_half_angle", 4.0, cg.Status.INVALID_ARGUMENT),
        ("follow_oncoming_weight", 1.5, cg.Status.INVALID_ARGUMENT),
        ("follow_glance_cue_weight", -0.1, cg.Status.INVALID_ARGUMENT),
        ("follow_glance_min", 3.0, cg.Status.INVALID_ARGUMENT),
        ("follow_glance_max", 601.0, cg.Status.INVALID_ARGUMENT),
        ("follow_forget_time", 3601.0, cg.Status.INVALID_ARGUMENT),
        ("street_latency_min", float("nan"), cg.Status.NON_FINITE),
        ("street_civil_distance", float("inf"), cg.Status.NON_FINITE),
        ("follow_distance", float("-inf"), cg.Status.NON_FINITE),
        ("follow_glance_min", float("nan"), cg.Status.NON_FINITE),
    ],
)
def test_bad_street_and_following_settings_are_refused_by_name(field, value, status):
    with pytest.raises(cg.Error) as error:
        cg.Crowd(max_characters=1, **{field: value})
    assert error.value.status == status
    assert error.value.function == "cg_crowd_create"
    assert field in error.value.message


def test_following_beyond_the_view_distance_is_refused():
    with pytest.raises(cg.InvalidArgumentError) as error:
        cg.Crowd(cg.street_config(follow_distance=18.0), max_characters=1)
    assert "follow_distance" in error.value.message and "max_distance" in error.value.message
    # Off, the same distance is no error: it is never used.
    with cg.Crowd(max_characters=1, follow_distance=18.0) as crowd:
        assert crowd.config.follow_enabled == 0


def test_passers_by_glance_where_others_stare():
    crowd, ids, states, speeds = street(cg.street_config())
    seen_following = 0
    with crowd:
        for frame in range(1, 30 * FPS + 1):
            walk(crowd, states, speeds, frame)
            for me in ids[STARERS:]:
                point, _ = crowd.read_following(me)
                if point is not None:
                    seen_following += 1
                    assert point == pytest.approx(WINDOW, abs=1e-4)
        glances = [crowd.read_following(me).glances for me in ids]
    assert glances[:STARERS] == [0] * STARERS  # a starer's own target wins
    followers = sum(count > 0 for count in glances[STARERS:])
    assert followers >= WALKERS // 3, glances
    assert seen_following > FPS  # more than a second of glancing in all


def test_the_followed_point_is_in_the_crowds_units():
    centimetres_config = cg.street_config(max_distance=1700.0, follow_distance=1000.0,
                                          street_civil_distance=300.0,
                                          street_path_look_distance=400.0,
                                          street_civil_look_distance=200.0)
    crowd, ids, states, speeds = street(centimetres_config, units=100.0)
    followed = 0
    with crowd:
        for frame in range(1, 20 * FPS + 1):
            walk(crowd, states, speeds, frame, units=100.0)
            for me in ids[STARERS:]:
                point, _ = crowd.read_following(me)
                if point is not None:
                    assert np.allclose(point, np.array(WINDOW) * 100, atol=1e-2)
                    followed += 1
    assert followed > 0


def test_following_is_off_by_default():
    crowd, ids, states, speeds = street(cg.crowd_config(max_distance=17.0))
    with crowd:
        for frame in range(1, 20 * FPS + 1):
            walk(crowd, states, speeds, frame)
        assert all(crowd.read_following(me) == cg.Following(None, 0) for me in ids)


def test_read_following_refuses_bad_ids():
    with cg.Crowd(max_characters=2, max_objects=1) as crowd:
        thing = crowd.add_object((0.0, 1.0, 2.0))
        with pytest.raises(cg.NotFoundError):
            crowd.read_following(12345)
        with pytest.raises(cg.InvalidArgumentError):
            crowd.read_following(thing)
        with pytest.raises(OverflowError):
            crowd.read_following(2**32)
