"""One Python object owns each native handle (``cg_crowd*``, ``cg_view_blender*``), and no
call ever uses a handle that is being destroyed.

Ownership: an owner is initialised once (``__init__`` again raises ``RuntimeError``) and
cannot be copied or pickled (``copy.copy``, ``copy.deepcopy``, ``pickle`` raise
``TypeError``), so no two Python objects ever destroy the same handle.

Calls in flight: every method first converts and checks all its arguments (this is where
user code such as an argument's ``__float__`` or ``__index__`` runs), and only then takes
the handle through the owner's guard, a readers-writer lock:

- calls the C header declares on a ``const`` handle (reads), and ``Crowd.step_range`` and
  ``Crowd.push_range``, which C allows on several threads at once, hold it *shared*, so they
  still run concurrently;
- calls that change the object hold it *exclusively*, so two Python threads can no longer
  mutate one object at the same time (the C library does not allow it: they now take
  turns);
- ``close()`` holds it exclusively: called from another thread while calls are in flight,
  it **waits** for them to return, then destroys the handle; calls that start later raise
  ``ValueError`` (closed).

ctypes releases the GIL during a C call, so the guard is what keeps ``close()`` on another
thread from freeing the handle under a running ``step()``.

Re-entrance: a thread that holds the guard and calls ``close()`` (or any other method) on
the same object raises ``RuntimeError`` instead of waiting for itself. Since arguments are
converted before the guard is taken, an argument's ``__float__`` that calls ``close()``
simply closes the object first, and the call then raises ``ValueError`` (closed); the
error can only come from code running while a call holds the guard, such as a finalizer
the garbage collector runs at that moment.

The raw handle (``owner.handle``) used with ``crowdgaze.lib`` directly bypasses all this.
"""

from __future__ import annotations

import threading
from typing import Any

from . import _exceptions as e

#: Serialises the check-and-set of a new owner's handle (re-``__init__`` from two threads).
_INIT_LOCK = threading.Lock()


class Guard:
    """A fair (first come, first served) readers-writer lock that refuses re-entrance from
    the thread holding it. Consecutive shared requests enter together; an exclusive one
    waits for the holders before it to leave, and everyone after it waits for it, so a
    thread calling ``step()`` in a loop cannot starve ``close()`` on another thread."""

    __slots__ = ("_condition", "_shared", "_exclusive", "_holders", "_next", "_head",
                 "_abandoned", "_waiting")

    def __init__(self):
        self._condition = threading.Condition(threading.Lock())
        self._shared = 0  # threads holding it shared
        self._exclusive = None  # the thread holding it exclusively
        self._holders = set()  # every thread holding it (each at most once)
        self._next = 0  # the ticket the next request takes
        self._head = 0  # the ticket whose turn it is
        self._abandoned = set()  # tickets of requests interrupted while waiting
        self._waiting = 0  # requests waiting for their turn (no one to wake if 0)

    def _may_enter(self, ticket: int, exclusive: bool) -> bool:
        if ticket != self._head:
            return False
        if exclusive:
            return self._shared == 0 and self._exclusive is None
        return self._exclusive is None

    def _advance(self) -> None:
        self._head += 1
        while self._head in self._abandoned:
            self._abandoned.discard(self._head)
            self._head += 1

    def acquire(self, exclusive: bool, where: str, kind: str) -> None:
        me = threading.get_ident()
        with self._condition:
            if me in self._holders:
                raise e.state_error(
                    f"{where}: called while a call on this {kind} is in flight on the same "
                    f"thread (from code that call ran, e.g. a finalizer); call it after that "
                    f"call returns"
                )
            ticket = self._next
            self._next += 1
            if not self._may_enter(ticket, exclusive):
                self._waiting += 1
                try:
                    while not self._may_enter(ticket, exclusive):
                        self._condition.wait()
                except BaseException:  # interrupted (KeyboardInterrupt): give up the turn
                    if ticket == self._head:
                        self._advance()
                    else:
                        self._abandoned.add(ticket)
                    self._condition.notify_all()
                    raise
                finally:
                    self._waiting -= 1
            self._advance()
            if exclusive:
                self._exclusive = me
            else:
                self._shared += 1
            self._holders.add(me)
            if self._waiting:
                self._condition.notify_all()  # the next in line may enter too (shared)

    def release(self, exclusive: bool) -> None:
        with self._condition:
            self._holders.discard(threading.get_ident())
            if exclusive:
                self._exclusive = None
            else:
                self._shared -= 1
            if self._waiting:
                self._condition.notify_all()


class _Call:
    """``with owner._call(where, exclusive) as handle``: the live handle, held."""

    __slots__ = ("_owner", "_where", "_exclusive")

    def __init__(self, owner, where: str, exclusive: bool):
        self._owner, self._where, self._exclusive = owner, where, exclusive

    def __enter__(self):
        owner = self._owner
        guard = owner._guard
        if guard is None:
            raise e.closed_error(f"{self._where}: this {owner._kind} was never initialised")
        guard.acquire(self._exclusive, self._where, owner._kind)
        handle = owner._handle
        if not handle:
            guard.release(self._exclusive)
            raise e.closed_error(f"{self._where}: the {owner._kind} is closed")
        return handle

    def __exit__(self, *exc) -> None:
        self._owner._guard.release(self._exclusive)


class HandleOwner:
    """Base of ``Crowd`` and ``ViewBlender``: the handle, its guard and its lifetime.

    Subclasses set ``_kind`` (for messages) and ``_destroy`` (the C destroy function), and
    call ``_refuse_reinit`` first and ``_adopt`` last in ``__init__``.
    """

    _kind = "object"
    _destroy: Any = None
    #: The handle (a ctypes pointer), None once closed or before ``__init__``.
    _handle = None
    #: The guard, set once by ``_adopt``; None means never initialised.
    _guard = None

    def _refuse_reinit(self, where: str) -> None:
        if self._guard is not None:
            raise e.state_error(
                f"{where}: this {type(self).__name__} is already initialised (it owns a "
                f"native handle); create a new {type(self).__name__} instead"
            )

    def _adopt(self, handle, where: str) -> None:
        with _INIT_LOCK:
            if self._guard is None:
                self._guard = Guard()
                self._handle = handle
                return
        type(self)._destroy(handle)  # initialised by another thread meanwhile
        self._refuse_reinit(where)

    def _call(self, where: str, exclusive: bool = False) -> _Call:
        return _Call(self, where, exclusive)

    @property
    def handle(self):
        """The raw handle (a ctypes pointer), for calling ``crowdgaze.lib`` directly; such
        calls bypass the checks and the guard of the methods."""
        handle = self._handle
        if not handle:
            raise e.closed_error(f"the {self._kind} is closed")
        return handle

    @property
    def closed(self) -> bool:
        """True once ``close()`` was called (or if ``__init__`` failed)."""
        return not self._handle

    def close(self) -> None:
        """Destroys the native object; later calls raise ``ValueError``. Closing twice is
        fine. From another thread, waits until the calls in flight have returned."""
        guard = self._guard
        if guard is None:
            return
        guard.acquire(True, f"{type(self).__name__}.close", self._kind)
        try:
            handle, self._handle = self._handle, None
            if handle:
                type(self)._destroy(handle)
        finally:
            guard.release(True)

    def __repr__(self) -> str:
        name = f"crowdgaze.{type(self).__name__}"
        if self._guard is None:
            return f"<{name}: not initialised>"
        if not self._handle:
            return f"<{name}: closed>"
        try:
            return f"<{name}: {self._describe()}>"
        except Exception:  # e.g. from a finalizer while a call is in flight: no details
            return f"<{name}>"

    def _describe(self) -> str:
        """What ``repr`` shows of a live object."""
        return "open"

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        self.close()

    # --- one owner per handle -----------------------------------------------------------

    def _refuse_copy(self, what: str):
        name = type(self).__name__
        raise e.type_error(
            f"{name} objects cannot be {what}: each owns a native handle that only it may "
            f"destroy; create another {name} from the same config instead"
        )

    def __copy__(self):
        self._refuse_copy("copied")

    def __deepcopy__(self, memo):
        self._refuse_copy("copied")

    def __reduce__(self):
        self._refuse_copy("pickled")

    def __reduce_ex__(self, protocol):
        self._refuse_copy("pickled")

    def __getstate__(self):
        self._refuse_copy("pickled")

    def __setstate__(self, state):
        self._refuse_copy("unpickled")
