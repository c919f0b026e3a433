"""The exceptions of the package: ``crowdgaze.Error`` and its subclasses, one per kind of
failure, each also deriving from the matching built-in exception.

Every exception the package raises on purpose is a ``crowdgaze.Error``, whether the C
library refused the call (``function`` is then the C function) or the binding refused an
argument before any C call (``function`` is None; the message starts with the Python
function and names the argument). So ``except crowdgaze.Error`` catches them all, and
``except ValueError`` (or ``LookupError``, ``TypeError``, ...) catches the same errors a
Python library would raise there:

=====================  =====================================  ==========================
class                  statuses                               also a
=====================  =====================================  ==========================
InvalidArgumentError   INVALID_ARGUMENT, NULL_ARGUMENT,       ValueError
                       BAD_STRUCT_SIZE
NonFiniteError         NON_FINITE                             InvalidArgumentError
ArgumentRangeError     (binding) an integer out of its C      InvalidArgumentError,
                       type's range                           OverflowError
ArgumentTypeError      (binding) a wrong type                 TypeError
FieldError             (binding) no such field, or a          AttributeError
                       read-only struct
NotFoundError          NOT_FOUND                              LookupError
CapacityError          CAPACITY                               RuntimeError
WrongStateError        WRONG_STATE                            RuntimeError
ClosedError            (binding) a closed crowd, blender, rig  WrongStateError, ValueError
NotConvergedError      NOT_CONVERGED                          RuntimeError
InternalError          INTERNAL, POISONED                     RuntimeError
OutOfMemoryError       OUT_OF_MEMORY                          MemoryError
=====================  =====================================  ==========================

``crowdgaze.Error(status, message, function)`` builds the subclass of ``status``.
"""

from __future__ import annotations

from typing import Any

from ._native import Status


class Error(Exception):
    """A failed crowdgaze call, the base of every exception the package raises.

    ``status`` is the ``crowdgaze.Status`` (an ``int``; the status the C library gives for
    such an error when the binding refused the call itself), ``message`` the one-line
    explanation (``cg_last_error_message``, or the binding's), ``function`` the C function
    that failed, or None when the binding refused the call before calling C.
    """

    status: Status | int
    message: str
    function: str | None

    def __new__(
        cls, status: int, message: str = "", function: str | None = None
    ) -> Error:
        if cls is Error:
            cls = CLASSES.get(int(status), Error)
        # Exception's, not the next in the MRO: MemoryError's refuses subclasses of Error.
        instance: Error = Exception.__new__(cls, status, message, function)
        return instance

    def __init__(self, status: int, message: str = "", function: str | None = None):
        try:
            self.status = Status(status)
        except ValueError:
            self.status = status
        self.message = message
        self.function = function
        text = message or _status_text(self.status)
        super().__init__(f"{function}: {text}" if function else text)

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (int(self.status), self.message, self.function))


def _status_text(status: int) -> str:
    """The library's description of ``status`` (``cg_status_str``)."""
    from ._library import lib  # loaded by then: only raised errors get here

    text: bytes = lib.cg_status_str(int(status) & 0xFFFFFFFF)
    return text.decode("utf-8")


class InvalidArgumentError(Error, ValueError):
    """An argument the library or the binding refuses (``INVALID_ARGUMENT``,
    ``NULL_ARGUMENT``, ``BAD_STRUCT_SIZE``)."""


class NonFiniteError(InvalidArgumentError):
    """A NaN or infinite number where a finite one is needed (``NON_FINITE``)."""


class ArgumentRangeError(InvalidArgumentError, OverflowError):
    """An integer outside its C type's range, or a real number too large for a C float."""


class ArgumentTypeError(Error, TypeError):
    """An argument of the wrong type (refused by the binding before any C call)."""


class FieldError(Error, AttributeError):
    """An assignment to a name that is no field of the struct, or to a read-only copy such
    as ``Crowd.config``."""


class NotFoundError(Error, LookupError):
    """An id that names no character, object, conversation or key (``NOT_FOUND``)."""


class CapacityError(Error, RuntimeError):
    """A fixed capacity of the config is reached (``CAPACITY``)."""


class WrongStateError(Error, RuntimeError):
    """A call at the wrong time: a step or push is open, a plan is active, nothing is
    recorded, a call re-entered from a finalizer (``WRONG_STATE``)."""


class ClosedError(WrongStateError, ValueError):
    """A call on a closed (or never initialised) ``Crowd``, ``ViewBlender`` or ``Rig``; a
    ``ValueError`` too, as for a closed file."""


class NotConvergedError(Error, RuntimeError):
    """An iteration stopped at its limit (``NOT_CONVERGED``)."""


class InternalError(Error, RuntimeError):
    """A bug in the library (``INTERNAL``; ``POISONED``: an earlier internal error left the
    object unusable)."""


class OutOfMemoryError(Error, MemoryError):
    """An allocation failed (``OUT_OF_MEMORY``)."""


#: Status -> the class ``Error(status, ...)`` builds.
CLASSES: dict[int, type[Error]] = {
    Status.NULL_ARGUMENT: InvalidArgumentError,
    Status.INVALID_ARGUMENT: InvalidArgumentError,
    Status.NON_FINITE: NonFiniteError,
    Status.NOT_FOUND: NotFoundError,
    Status.CAPACITY: CapacityError,
    Status.BAD_STRUCT_SIZE: InvalidArgumentError,
    Status.WRONG_STATE: WrongStateError,
    Status.NOT_CONVERGED: NotConvergedError,
    Status.INTERNAL: InternalError,
    Status.OUT_OF_MEMORY: OutOfMemoryError,
    Status.POISONED: InternalError,
}


def type_error(message: str) -> ArgumentTypeError:
    """The binding's refusal of an argument's type (a ``TypeError``)."""
    return ArgumentTypeError(Status.INVALID_ARGUMENT, message)


def value_error(message: str) -> InvalidArgumentError:
    """The binding's refusal of an argument's value, shape or layout (a ``ValueError``)."""
    return InvalidArgumentError(Status.INVALID_ARGUMENT, message)


def range_error(message: str) -> ArgumentRangeError:
    """The binding's refusal of a number out of its C type's range (an ``OverflowError``
    and a ``ValueError``)."""
    return ArgumentRangeError(Status.INVALID_ARGUMENT, message)


def not_found_error(message: str) -> NotFoundError:
    """An id the binding finds nowhere (a ``LookupError``)."""
    return NotFoundError(Status.NOT_FOUND, message)


def state_error(message: str) -> WrongStateError:
    """A call the binding refuses at this time (a ``RuntimeError``)."""
    return WrongStateError(Status.WRONG_STATE, message)


def closed_error(message: str) -> ClosedError:
    """A call on a closed object (a ``ValueError`` and a ``RuntimeError``)."""
    return ClosedError(Status.WRONG_STATE, message)
