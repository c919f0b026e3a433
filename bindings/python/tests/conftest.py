"""pytest setup: import the package from this source tree (``bindings/python``), whatever
the current directory. The library is the one ``crowdgaze.find_library`` picks:
``scripts/test`` sets ``CROWDGAZE_LIBRARY`` to the one its ``cargo test`` just built."""

import sys
from pathlib import Path

import pytest

PACKAGE_ROOT = Path(__file__).resolve().parents[1]
REPOSITORY = PACKAGE_ROOT.parents[1]
if str(PACKAGE_ROOT) not in sys.path:
    sys.path.insert(0, str(PACKAGE_ROOT))


@pytest.fixture(scope="session")
def header_text() -> str:
    return (REPOSITORY / "include" / "crowdgaze.h").read_text()
