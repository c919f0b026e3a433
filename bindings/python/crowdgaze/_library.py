"""The loaded shared library, with every function declared (see ``_native.load``)."""

from . import _native

#: The ``ctypes.CDLL`` of crowdgaze; each ``cg_`` function has its ``argtypes``/``restype``.
lib = _native.load()
#: The path it was loaded from.
library_path: str = lib._name
