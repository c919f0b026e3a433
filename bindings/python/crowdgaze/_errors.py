"""``crowdgaze.Error`` and the status check every wrapper call goes through."""

from __future__ import annotations

import ctypes

from . import _checks as c
from . import _native as n
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


class Error(Exception):
    """A failed crowdgaze call.

    ``status`` is the ``crowdgaze.Status`` (an ``int``), ``message`` the library's one-line
    explanation (``cg_last_error_message``), ``function`` the C function that failed.
    """

    def __init__(self, status: int, message: str, function: str | None = None):
        try:
            self.status = n.Status(status)
        except ValueError:
            self.status = status
        self.message = message
        self.function = function
        text = message or status_string(status)
        super().__init__(f"{function}: {text}" if function else text)


def check(status: int, function: str) -> None:
    """Raises ``Error`` unless ``status`` is ``CG_STATUS_OK``."""
    if status != n.Status.OK:
        raise Error(status, last_error_message(), function)


def check_converged(status: int, function: str) -> bool:
    """Like ``check``, but ``NOT_CONVERGED`` (outputs written) returns False."""
    if status == n.Status.NOT_CONVERGED:
        return False
    check(status, function)
    return True
