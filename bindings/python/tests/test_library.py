"""Where the binding finds the shared library."""

import os

import pytest

import crowdgaze as cg
from crowdgaze import _native


def test_the_environment_variable_wins(monkeypatch, tmp_path):
    monkeypatch.setenv("CROWDGAZE_LIBRARY", str(tmp_path / "missing.so"))
    with pytest.raises(OSError, match="CROWDGAZE_LIBRARY"):
        _native.find_library()
    monkeypatch.setenv("CROWDGAZE_LIBRARY", cg.library_path)
    assert str(_native.find_library()) == cg.library_path


def test_the_newest_cargo_build_is_used(monkeypatch, tmp_path):
    monkeypatch.delenv("CROWDGAZE_LIBRARY", raising=False)
    monkeypatch.setenv("CARGO_TARGET_DIR", str(tmp_path))
    for profile, mtime in (("release", 1_000_000), ("debug", 2_000_000)):
        (tmp_path / profile).mkdir()
        library = tmp_path / profile / "libcrowdgaze.so"
        library.write_bytes(b"")
        os.utime(library, (mtime, mtime))
    assert _native.find_library() == tmp_path / "debug" / "libcrowdgaze.so"
    os.utime(tmp_path / "release" / "libcrowdgaze.so", (3_000_000, 3_000_000))
    assert _native.find_library() == tmp_path / "release" / "libcrowdgaze.so"


def test_nothing_found_says_where_it_looked(monkeypatch, tmp_path):
    monkeypatch.delenv("CROWDGAZE_LIBRARY", raising=False)
    monkeypatch.setenv("CARGO_TARGET_DIR", str(tmp_path))
    with pytest.raises(OSError, match="cargo build --release"):
        _native.find_library()


def test_loading_declares_every_function():
    library = _native.load(cg.library_path)
    assert library.cg_crowd_step.argtypes == cg.lib.cg_crowd_step.argtypes
    assert library.cg_version_string().decode() == cg.__version__
