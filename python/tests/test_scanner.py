"""ldoem.Scanner over the emulator: the calls, the profile arrays, the errors."""

import socket
import time

import numpy as np
import pytest

import ldoem


@pytest.fixture
def emulator():
    with ldoem.Emulator("minimal", transports=("tcp", "serial"), virtual_time=True) as emu:
        yield emu


def test_version_is_the_projects():
    assert ldoem.__version__.count(".") == 2


def test_identify_status_and_configuration(emulator):
    with ldoem.Scanner(emulator.tcp) as scanner:
        assert scanner.state == "connected"
        status = scanner.status()
        assert status["sensor"] == "IDLE" and status["status_byte"] == 0x01
        identification = scanner.identify()
        assert len(identification) == 11 and all(isinstance(text, str) for text in identification.values())
        scanner.configure(motor_speed_hz=8, angle_step_deg=0.5)
        assert scanner.global_config()["motor_speed_hz"] == 8
        assert scanner.global_config()["angle_step_deg"] == 0.5
        scanner.write_sectors([(3, 45.0), (1, 359.875)])
        table = scanner.sectors()
        assert [(s["function"], s["stop_deg"]) for s in table[:2]] == [(3, 45.0), (1, 359.875)]


@pytest.mark.parametrize("transport", ["tcp", "serial"])
def test_profiles_are_structured_arrays_and_the_stream_an_iterator(emulator, transport):
    endpoint = emulator.tcp if transport == "tcp" else emulator.serial
    with ldoem.Scanner(endpoint) as scanner:
        assert scanner.rotate()["sensor"] == "ROTATE"
        assert scanner.measure()["sensor"] == "MEASURE"
        with scanner.profiles(count=3) as stream:
            profiles = list(stream)
        assert len(profiles) == 3
        assert [p.profile_sent for p in profiles] == [1, 2, 3]
        points = profiles[0].points
        assert points.dtype == ldoem.PROFILE_DTYPE
        assert set(points.dtype.names) == {"sector", "angle", "range", "echo", "time"}
        # minimal.yaml: a wall 5 m ahead (its face at 5.0 m): straight ahead the range is 5.0.
        ahead = points[np.abs(points["angle"]) < 0.2]
        assert len(ahead) > 0 and np.allclose(ahead["range"], 5.0, atol=0.05)
        assert np.all(np.diff(points["time"][points["sector"] == points["sector"][0]]) >= 0)
        assert scanner.state == "connected"


def test_an_endless_stream_is_stopped_on_leaving_the_block(emulator):
    with ldoem.Scanner(emulator.tcp) as scanner:
        scanner.rotate()
        scanner.measure()
        with scanner.profiles() as stream:
            for seen, _ in enumerate(stream, 1):
                if seen == 5:
                    break
        assert scanner.state == "connected"
        assert scanner.status()["sensor"] == "MEASURE"


def test_a_bad_endpoint_is_a_value_error_with_libldoems_message():
    with pytest.raises(ValueError, match="endpoint `can:vcan0:800:6C1`: out of range"):
        ldoem.Scanner("can:vcan0:800:6C1")


def test_an_old_spelling_is_a_value_error_naming_the_new_one():
    # docs/endpoints.md: the grammar of every tool; a spelling from before it names the new one.
    with pytest.raises(ValueError, match=r"`pty:/tmp/x` is the old spelling; write lpt:pty:/tmp/x"):
        ldoem.Scanner("tcp:127.0.0.1:1", lpt="pty:/tmp/x")
    with pytest.raises(ValueError, match=r"write tcp:127.0.0.1:49152"):
        ldoem.Scanner("127.0.0.1:49152")


def test_a_refused_connection_is_an_ldoem_error_with_its_kind():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    with pytest.raises(ldoem.Error) as caught:
        ldoem.Scanner(f"tcp:127.0.0.1:{port}")
    assert caught.value.kind in ("connection_closed", "system", "timeout")
    assert f"127.0.0.1:{port}" in str(caught.value)


def test_a_service_failure_carries_the_protocol_reason(emulator):
    with ldoem.Scanner(emulator.tcp) as scanner:
        with pytest.raises(ldoem.ServiceFailure) as caught:
            scanner.measure()  # from IDLE: not allowed in this state (spec 5, D2 reason 3)
        error = caught.value
        assert error.kind == "service_failure"
        assert error.failure_reason == 3 and error.code == 3
        assert error.request == "TRANS_MEASURE"
        assert error.retryable is False
        assert "TRANS_MEASURE" in str(error)


def test_a_dropped_reply_is_a_timeout_at_the_calls_own_deadline(emulator):
    emulator.inject_fault("drop_reply", on={"service": "GET_STATUS", "nth": 2})
    with ldoem.Scanner(emulator.tcp, request_timeout=0.3) as scanner:
        with pytest.raises(ldoem.Timeout) as caught:
            scanner.status()
        assert caught.value.retryable and caught.value.recovery == "retry"
        assert scanner.status()["sensor"] == "IDLE"


def test_power_cycle_costs_the_connection_and_reconnect_brings_it_back(emulator):
    # A closed connection today; a silent device that the host's timeout notices once power cuts
    # are as on the hardware (issue 25 item 0): reconnect is the answer to both.
    with ldoem.Scanner(emulator.tcp, request_timeout=0.5, reconnect_attempts=40, reconnect_interval=0.25) as scanner:
        scanner.rotate()
        emulator.power_cycle(off_s=0.5)
        with pytest.raises(ldoem.Error) as caught:
            for _ in range(50):
                scanner.status()
        assert caught.value.kind in ("connection_closed", "timeout")
        assert scanner.reconnect()["sensor"] == "IDLE"


def test_the_tilt_stepper_on_the_lpt_line():
    with ldoem.Emulator("minimal", transports=("tcp", "lpt"), virtual_time=True) as emulator:
        with ldoem.Scanner(emulator.device, lpt=emulator.lpt) as scanner:
            assert scanner.tilt_deg == 0.0
            assert scanner.move_tilt(10, rate_hz=2000) == pytest.approx(0.9)   # D8: 1.8 deg / 20 a step
            # The emulated plate saw the 10 steps (it reads the pty as the bytes come).
            deadline = time.monotonic() + 5
            while emulator.query_status()["tilt_steps"] != 10 and time.monotonic() < deadline:
                time.sleep(0.05)
            assert emulator.query_status()["tilt_steps"] == 10
            assert scanner.move_tilt(-3, half_step=True, rate_hz=2000) == pytest.approx(0.9 - 3 * 0.045)
            assert scanner.tilt_to(0.0, half_step=True, rate_hz=2000) == pytest.approx(0.0)
            with pytest.raises(ValueError, match="20000"):
                scanner.move_tilt(20001)


def test_without_an_lpt_endpoint_the_tilt_is_a_value_error(emulator):
    with ldoem.Scanner(emulator.tcp) as scanner:
        with pytest.raises(ValueError, match="lpt"):
            scanner.move_tilt(1)


def test_an_error_in_a_stream_block_is_the_one_raised_not_the_failing_cancel(emulator):
    with ldoem.Scanner(emulator.tcp) as scanner:
        scanner.rotate()
        scanner.measure()
        with pytest.raises(ldoem.Error) as caught:
            with scanner.profiles(timeout=1.0) as stream:
                next(stream)
                emulator.inject_fault("tcp_reset")  # the next telegram resets the connection
                for _ in stream:
                    pass
        assert caught.value.operation != "CANCEL_PROFILE"
