"""ldoem for Python: libldoem's Scanner, ldoem-scan's 3D scan, the ldoem-emud emulator and its
control socket, a pytest fault-matrix plugin and `python3 -m ldoem.torture` (docs/python.md)."""

from ._errors import ConnectionClosed, DeviceFault, Error, Refused, ServiceFailure, Timeout
from .control import ControlClient, ControlError
from .emulator import Emulator, EmulatorError

_EXTENSION_NAMES = ("FORMAT_RANGE", "FORMAT_RANGE_ECHO", "PROFILE_DTYPE", "SCAN_FIELDS", "Profile", "ProfileStream",
                    "Scanner", "__version__", "scan")
try:
    from ._ldoem import (FORMAT_RANGE, FORMAT_RANGE_ECHO, PROFILE_DTYPE, SCAN_FIELDS, Profile, ProfileStream,
                         Scanner, __version__, scan)
except ImportError as _failure:
    # The pytest plugin loads this package in every pytest run of the machine: a broken extension
    # (another interpreter's ABI, numpy missing) must cost only what needs it, with the reason.
    _extension_error = _failure

    def __getattr__(name):
        if name in _EXTENSION_NAMES:
            raise ImportError(f"ldoem.{name} needs the extension module ldoem._ldoem: {_extension_error}")
        raise AttributeError(f"module 'ldoem' has no attribute {name!r}")

__all__ = [
    "ConnectionClosed", "ControlClient", "ControlError", "DeviceFault", "Emulator", "EmulatorError", "Error",
    "Refused", "ServiceFailure", "Timeout", *_EXTENSION_NAMES,
]
