"""Packaging: what git ignores, the wheel's platform tag."""

import os
import subprocess
from pathlib import Path

import pytest

PACKAGE_ROOT = Path(__file__).resolve().parents[1]


def test_the_library_of_an_editable_install_is_ignored_by_git():
    repository = PACKAGE_ROOT.parents[1]
    if not (repository / ".git").exists():
        pytest.skip("not a git checkout")
    for name in ("_crowdgaze.abi3.so", "_crowdgaze.cpython-311-x86_64-linux-gnu.so"):
        path = f"bindings/python/crowdgaze/{name}"
        result = subprocess.run(["git", "check-ignore", "-q", path], cwd=repository)
        assert result.returncode == 0, f"{path} is not ignored by .gitignore"


def test_a_wheel_pip_builds_gets_the_manylinux_tag(monkeypatch):
    maturin = pytest.importorskip("maturin")
    monkeypatch.syspath_prepend(str(PACKAGE_ROOT / "build_backend"))
    monkeypatch.chdir(PACKAGE_ROOT)  # where PEP 517 hooks run: maturin reads pyproject.toml
    monkeypatch.delenv("MATURIN_PEP517_ARGS", raising=False)
    import crowdgaze_build

    calls = []
    monkeypatch.setattr(maturin, "build_wheel", lambda *args: calls.append(args) or "w.whl")
    assert crowdgaze_build.build_wheel("dist") == "w.whl"
    assert calls[-1][1]["maturin.build-args"] == ["--compatibility", "manylinux_2_34"]
    # Arguments that name a compatibility win.
    crowdgaze_build.build_wheel("dist", {"build-args": "--compatibility linux -v"})
    assert calls[-1][1] == {"maturin.build-args": ["--compatibility", "linux", "-v"]}
    text = (PACKAGE_ROOT / "pyproject.toml").read_text()
    assert 'build-backend = "crowdgaze_build"' in text


def test_the_installed_wheel_is_tagged_manylinux():
    """With scripts/test's venv (``$CG_PYTHON``, where ``pip install ./bindings/python``
    put the package): the wheel pip built and installed has the manylinux tag."""
    python = os.environ.get("CG_PYTHON")
    if not python:
        pytest.skip("CG_PYTHON (the venv scripts/test installs the wheel into) is not set")
    code = (
        "import importlib.metadata as m; "
        "print(m.distribution('crowdgaze').read_text('WHEEL'))"
    )
    wheel = subprocess.run([python, "-c", code], capture_output=True, text=True, check=True)
    tags = [line.split(":", 1)[1].strip() for line in wheel.stdout.splitlines()
            if line.startswith("Tag:")]
    assert tags and all("manylinux_2_34" in tag for tag in tags), wheel.stdout
