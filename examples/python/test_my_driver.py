"""A small driver tested under the fault matrix: the example of docs/python.md's plugin section.

    PYTHONPATH=build/default/python python3 -m pytest examples/python/test_my_driver.py --junitxml=matrix.xml

`read_profiles` is the driver under test: it reads N profiles and rides out what the device can
recover from: a lost reply (retry), a lost connection (reconnect), a device fault or a refusal in
ERROR (DO_RESET level 2, once the cause is gone: docs/faults.md "Host side"), a bounded number of
times. The matrix runs it once per fault that applies to TCP, at each trigger point; each run must
end with N profiles (the matrix's device faults last one second).
"""

import time

import pytest

import ldoem


def read_profiles(endpoint, count, attempts=6):
    """The driver: `count` profiles from a measuring scanner."""
    scanner = None
    last = None
    for _ in range(attempts):
        try:
            if scanner is None:
                scanner = ldoem.Scanner(endpoint, request_timeout=1.0, reconnect_interval=0.25, reconnect_attempts=20)
            elif last.recovery == "reconnect" or scanner.state == "closed":
                scanner.reconnect()
            if scanner.status()["sensor"] != "IDLE" or (last is not None and last.recovery != "retry"):
                scanner.reset(2)  # back to IDLE: after a fault, a reset, or a stream left running
            scanner.configure(motor_speed_hz=10)
            scanner.rotate()
            scanner.measure()
            with scanner.profiles(count=count, timeout=1.0) as stream:
                return list(stream)
        except ldoem.Error as error:
            if error.recovery == "none" and error.kind != "service_failure":
                raise  # a bug of ours, not the device's
            last = error
            time.sleep(0.3)  # the device's own time to get over it
    raise last


@pytest.mark.ldoem_faults("tcp")
def test_driver(ldoem_emulator, ldoem_scenario):
    profiles = read_profiles(ldoem_emulator.device, 10)
    assert len(profiles) == 10
