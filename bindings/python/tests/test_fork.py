"""A crowd with worker threads used in a child after ``os.fork``: in the child, the crowd
rebuilds its worker pool on its next step, which gives what the parent's step gives."""

import os
import signal
import subprocess
import sys
import textwrap

import pytest

import crowdgaze as cg

from conftest import PACKAGE_ROOT

#: Runs in a child Python: makes a crowd with 2 worker threads, steps it, forks; the forked
#: child steps it once more and writes its joints to a pipe, the parent does the same step
#: and compares.
SCRIPT = textwrap.dedent(
    """
    import os, sys
    import numpy as np
    import crowdgaze as cg

    crowd = cg.Crowd(max_characters=64, threads=2, seed=3)
    ids = [crowd.add_character((x % 8, 0, x // 8), heading=0.3 * x) for x in range(64)]
    for _ in range(3):
        crowd.step(1 / 30)  # the workers are running now
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read)
        try:
            crowd.step(1 / 30)
            data = crowd.read_joints().tobytes()
            with os.fdopen(write, "wb") as pipe:
                pipe.write(data)
        finally:
            os._exit(0)
    os.close(write)
    crowd.step(1 / 30)
    mine = crowd.read_joints().tobytes()
    with os.fdopen(read, "rb") as pipe:
        theirs = pipe.read()
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0, status
    assert theirs == mine, f"the child's step differs ({len(theirs)} bytes, {len(mine)})"
    print("same step")
    """
)


@pytest.mark.fork
def test_fork_child_steps():
    """A hang (the child waiting for workers that fork did not copy) fails after the
    timeout instead of hanging the suite: the whole process group is killed."""
    child = subprocess.Popen(
        [sys.executable, "-c", SCRIPT],
        cwd=PACKAGE_ROOT,
        env=dict(os.environ, CROWDGAZE_LIBRARY=cg.library_path),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, the forked child included
    )
    try:
        stdout, stderr = child.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        child.communicate()
        pytest.fail("a crowd with threads=2 hangs in a child after os.fork (20 s timeout)")
    assert child.returncode == 0 and "same step" in stdout, stderr[-3000:]
