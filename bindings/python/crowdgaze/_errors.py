"""The status check every wrapper call goes through (the exceptions are in
``crowdgaze._exceptions``)."""

from __future__ import annotations

import ctypes

from . import _checks as c
from . import _native as n
from ._exceptions import Error
from ._library import lib


def last_error_message() -> str:
    """The calling thread's last error message (``cg_last_error_message``)."""
    length = lib.cg_last_error_message(None, 0)
    buffer = ctypes.create_string_buffer(length + 1)
    lib.cg_last_error_message(buffer, len(buffer))
    return buffer.value.decode("utf-8", errors="replace")


def status_string(status: int) -> str:
    """The static description of a status (``cg_status_str``)."""
    status = c.integer(status, "status_string", "status")
    return lib.cg_status_str(status).decode("utf-8")


def check(status: int, function: str) -> None:
    """Raises the ``Error`` subclass of ``status`` unless ``status`` is ``CG_STATUS_OK``."""
    if status != n.Status.OK:
        raise Error(status, last_error_message(), function)


def check_converged(status: int, function: str) -> bool:
    """Like ``check``, but ``NOT_CONVERGED`` (outputs written) returns False."""
    if status == n.Status.NOT_CONVERGED:
        return False
    check(status, function)
    return True
