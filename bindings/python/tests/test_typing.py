"""Typing and names: the package ships ``py.typed`` and passes mypy, a user's typed script
passes ``mypy --strict`` against it, ``__all__`` is the public API and every public
function, class and method has a docstring."""

import inspect
import os
import subprocess
import sys
import textwrap

import pytest

import crowdgaze as cg
from conftest import PACKAGE_ROOT

USER_SCRIPT = textwrap.dedent(
    """
    import numpy as np
    from numpy.typing import NDArray

    import crowdgaze as cg


    def gaze_of(crowd: cg.Crowd, ids: list[int]) -> NDArray[np.uint32]:
        crowd.step(1 / 30)
        gaze = crowd.read_gaze()
        targets: NDArray[np.uint32] = gaze["target"][crowd.rows_of(ids)]
        return targets


    config: cg.CrowdConfig = cg.crowd_config(max_characters=4, threads=1)
    with cg.Crowd(config) as crowd:
        ids = [crowd.add_character((0.0, 0.0, float(x))) for x in range(3)]
        states = cg.entity_states(ids, flags=cg.CG_STATE_TALKING | cg.StateFlag.HAS_VELOCITY)
        states["flags"][0] &= ~cg.CG_STATE_TALKING
        crowd.push_frame(0.0, states)
        print(gaze_of(crowd, ids), crowd.row_of(ids[0]), crowd.config.seed)
        try:
            crowd.remove_entity(99)
        except cg.NotFoundError as error:
            status: cg.Status | int = error.status
            print(status, error.function)

    street: cg.CrowdConfig = cg.street_config(follow_distance=8.0)
    with cg.Crowd(street, max_characters=2) as walkers:
        walker = walkers.add_character((0.0, 0.0, 0.0), attention_model=cg.AttentionModel.STREET)
        walkers.step(1 / 30)
        seen: cg.Following = walkers.read_following(walker)
        followed: tuple[float, float, float] | None = seen.point
        print(followed, seen.glances + 1)

    names = ["Hips", "Spine", "Neck", "Skull", "LeftUpLeg", "RightUpLeg"]
    offsets = [(0.0, 1.0, 0.0), (0.0, 0.2, 0.0), (0.0, 0.3, 0.0), (0.0, 0.1, 0.0),
               (0.1, 0.0, 0.0), (-0.1, 0.0, 0.0)]
    with cg.Rig(names, [None, 0, 1, 2, 0, 0], offsets, up=cg.Axis.POSITIVE_Y,
                bone_map={"Skull": cg.BoneRole.HEAD}) as rig, cg.Crowd(max_characters=1) as one:
        bones = np.tile(np.array([0, 0, 0, 1], np.float32), (rig.bone_count, 1))
        me = one.add_character(chain=rig.chain)
        one.set_base_pose(me, rig.base_pose(bones))
        one.step(1 / 30)
        rig.write_joints(one.read_joints(one.row_of(me), 1), bones)
        roles: NDArray[np.uint32] = rig.roles
        print(rig.report.splitlines()[0], cg.BoneRole(int(roles[3])), rig.chain_bones)
    """
)


def run_mypy(*args: str, cwd, env=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "mypy", *args], cwd=cwd, env=env, capture_output=True,
        text=True, timeout=300,
    )


def test_the_package_passes_mypy(tmp_path):
    pytest.importorskip("mypy")
    assert (PACKAGE_ROOT / "crowdgaze" / "py.typed").is_file()
    result = run_mypy("--cache-dir", str(tmp_path / "cache"), "-p", "crowdgaze",
                      cwd=PACKAGE_ROOT)
    assert result.returncode == 0, result.stdout + result.stderr


def test_a_typed_user_script_passes_mypy_strict(tmp_path):
    """The package found as an installed one (on the path, not a source given to mypy):
    without ``py.typed`` mypy would not read it."""
    pytest.importorskip("mypy")
    script = tmp_path / "user.py"
    script.write_text(USER_SCRIPT)
    env = dict(os.environ, PYTHONPATH=str(PACKAGE_ROOT), CROWDGAZE_LIBRARY=cg.library_path)
    env.pop("MYPYPATH", None)
    result = run_mypy("--strict", "--cache-dir", str(tmp_path / "cache"), "user.py",
                      cwd=tmp_path, env=env)
    assert result.returncode == 0, result.stdout + result.stderr
    run = subprocess.run([sys.executable, "user.py"], cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr


def test_all_is_the_public_api():
    public = {name for name in dir(cg) if not name.startswith("_")}
    modules = {name for name in public if inspect.ismodule(getattr(cg, name))}
    assert set(cg.__all__) - {"__version__"} == public - modules - {"annotations"}
    assert len(cg.__all__) == len(set(cg.__all__))


def test_every_public_function_class_and_method_has_a_docstring():
    missing = []
    for name in cg.__all__:
        value = getattr(cg, name)
        if inspect.isfunction(value) or inspect.isclass(value):
            if not inspect.getdoc(value):
                missing.append(name)
        if inspect.isclass(value) and value.__module__.startswith("crowdgaze"):
            for member, attribute in vars(value).items():
                if member.startswith("_") or not callable(attribute) and not isinstance(
                    attribute, property
                ):
                    continue
                if not getattr(attribute, "__doc__", None):
                    missing.append(f"{name}.{member}")
    assert not missing, f"public names without a docstring: {missing}"
