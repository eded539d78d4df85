"""ldoem for Python: libldoem's Scanner, ldoem-scan's 3D scan, the ldoem-emud emulator and its
control socket, a pytest fault-matrix plugin and `python3 -m ldoem.torture` (docs/python.md)."""

from ._errors import ConnectionClosed, DeviceFault, Error, Refused, ServiceFailure, Timeout
from ._ldoem import (FORMAT_RANGE, FORMAT_RANGE_ECHO, PROFILE_DTYPE, SCAN_FIELDS, Profile, ProfileStream,
                     Scanner, __version__, scan)
from .control import ControlClient, ControlError
from .emulator import Emulator, EmulatorError

__all__ = [
    "ConnectionClosed", "ControlClient", "ControlError", "DeviceFault", "Emulator", "EmulatorError", "Error", "FORMAT_RANGE",
    "FORMAT_RANGE_ECHO", "PROFILE_DTYPE", "Profile", "ProfileStream", "Refused", "SCAN_FIELDS", "Scanner",
    "ServiceFailure", "Timeout", "__version__", "scan",
]
