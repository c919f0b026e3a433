"""The wheel's build backend: maturin's, except that a wheel ``pip`` builds gets the platform
tag of ``[tool.maturin] compatibility`` (``manylinux_2_34``) rather than ``linux_x86_64``.

maturin's PEP 517 hooks pass ``--compatibility off`` unless the build arguments (the
``maturin.build-args`` config setting or ``$MATURIN_PEP517_ARGS``) name a compatibility,
which overrides pyproject.toml: so ``pip wheel`` would tag the wheel ``linux_x86_64``, which
pip only installs on the machine that built it. ``maturin build`` reads pyproject.toml
itself and needs none of this. Arguments that name a compatibility still win.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import maturin
from maturin import (  # noqa: F401  (the other hooks, as they are)
    build_editable,
    build_sdist,
    get_requires_for_build_editable,
    get_requires_for_build_sdist,
    get_requires_for_build_wheel,
    prepare_metadata_for_build_editable,
    prepare_metadata_for_build_wheel,
)


def build_wheel(
    wheel_directory: str,
    config_settings: Mapping[str, Any] | None = None,
    metadata_directory: str | None = None,
) -> str:
    """maturin's ``build_wheel`` with pyproject.toml's compatibility, unless the build
    arguments name one."""
    args = list(maturin.get_maturin_pep517_args(config_settings))
    compatibility = maturin.get_config().get("compatibility")
    if compatibility and not any(
        a.startswith(("--compatibility", "--manylinux")) for a in args
    ):
        args += ["--compatibility", compatibility]
    settings = dict(config_settings or {})
    settings.pop("build-args", None)
    settings["maturin.build-args"] = args
    return maturin.build_wheel(wheel_directory, settings, metadata_directory)
