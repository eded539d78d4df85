"""ldoem.Emulator and its control socket: the methods against the daemon's command table, the
fault and object commands, events."""

import inspect

import pytest

import ldoem
from ldoem.control import ControlClient, method_name


@pytest.fixture(scope="module")
def emulator():
    with ldoem.Emulator("minimal", virtual_time=True) as emu:
        yield emu


def named_parameters(function):
    parameters = inspect.signature(function).parameters.values()
    return {p.name for p in parameters if p.name != "self" and p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)}


def takes_any_keyword(function):
    return any(p.kind == p.VAR_KEYWORD for p in inspect.signature(function).parameters.values())


def test_every_command_has_a_method_with_its_arguments_and_no_more(emulator):
    table = emulator.control.query_commands()
    names = {command["name"] for command in table}
    assert {"inject-fault", "power-cycle", "query-status", "move-object", "query-commands"} <= names
    for command in table:
        method = getattr(ControlClient, method_name(command["name"]), None)
        assert method is not None, f"ControlClient lacks {command['name']}"
        arguments = set(command["arguments"])
        assert command["help"], f"{command['name']} has no help"
        assert set(command["schema"]) == arguments, f"{command['name']}: schema and arguments differ"
        named = named_parameters(method)
        assert named <= arguments, f"{command['name']}: {named - arguments} are not arguments of the command"
        if not takes_any_keyword(method):
            assert named == arguments, f"{command['name']}: the method lacks {arguments - named}"
    # And no method for a command the daemon does not know (besides the client's own helpers).
    own = {"execute", "events", "close"}
    methods = {name for name, _ in inspect.getmembers(ControlClient, inspect.isfunction) if not name.startswith("_")}
    assert methods - own == {method_name(name) for name in names}


def test_the_emulators_shortcuts_are_the_clients_methods(emulator):
    for name in ("inject_fault", "clear_fault", "query_faults", "query_status", "power_cycle", "move_object",
                 "add_object", "remove_object"):
        assert named_parameters(getattr(ldoem.Emulator, name)) <= named_parameters(getattr(ControlClient, name)) | {"kind"}


def test_inject_query_and_clear_a_fault(emulator):
    fault_id = emulator.inject_fault("motor_stall")
    assert fault_id > 0
    assert any(fault["id"] == fault_id for fault in emulator.query_faults())
    status = emulator.query_status()
    assert status["faults_active"] >= 1 and "counters" in status
    emulator.clear_fault(fault_id)
    kinds = [event["event"] for event in emulator.event_log()]
    assert "FAULT_INJECTED" in kinds and "FAULT_CLEARED" in kinds


def test_a_bad_fault_is_a_control_error_with_the_daemons_reason(emulator):
    with pytest.raises(ldoem.ControlError) as caught:
        emulator.inject_fault("no_such_kind")
    assert caught.value.error_class == "GenericError"
    assert "kind" in caught.value.desc


def test_events_are_an_iterator(emulator):
    client = ControlClient(emulator.control_path)
    try:
        client.inject_fault("blind", from_deg=10, to_deg=20, duration_s=1)
        names = [event["event"] for event in client.events(timeout=2.0)]
        assert "FAULT_INJECTED" in names
    finally:
        client.close()


def test_objects_at_runtime(emulator):
    emulator.add_object({"name": "crate", "box": {"size_m": [0.5, 0.5, 0.5]}, "pose": {"position_m": [2, 0, 0]}})
    emulator.move_object("crate", [3, 0, 0], rpy_deg=[0, 0, 45])
    emulator.control.remove_object("crate")
    names = [event["event"] for event in emulator.event_log()]
    assert {"OBJECT_ADDED", "OBJECT_MOVED", "OBJECT_REMOVED"} <= set(names)


def test_a_dict_scene_and_a_stop_that_always_ends_the_process():
    scene = {"objects": [{"name": "wall", "box": {"size_m": [0.2, 20, 6]}, "pose": {"position_m": [3.1, 0, 0]}}]}
    emulator = ldoem.Emulator(scene, virtual_time=True).start()
    pid = emulator.process.pid
    try:
        with ldoem.Scanner(emulator.device) as scanner:
            scanner.rotate()
            scanner.measure()
            scanner.start_stream(count=1)
            profile = scanner.next_profile()
            assert abs(profile.points["range"][abs(profile.points["angle"]) < 0.2].mean() - 3.0) < 0.05
    finally:
        status = emulator.stop()
    assert status == 0
    with pytest.raises(ProcessLookupError):
        import os
        os.kill(pid, 0)


def test_a_daemon_that_does_not_start_is_an_error_with_its_message(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("objects: [{name: x, box: {size_m: [-1, 1, 1]}}]\n")
    with pytest.raises(ldoem.emulator.EmulatorError, match="size_m"):
        ldoem.Emulator(str(bad)).start()


def test_the_recording_gives_the_profiles_device_times():
    with ldoem.Emulator("minimal", virtual_time=True, record=True) as emulator:
        with ldoem.Scanner(emulator.device) as scanner:
            scanner.rotate()
            scanner.measure()
            with scanner.profiles(count=4) as stream:
                counts = [profile.profile_count for profile in stream]
    times = emulator.profile_times()
    assert len(times) == 4 and times == sorted(times)
    # One revolution apart at the scene's 10 Hz (device time, D7).
    assert all(abs((b - a) * 10 - (cb - ca)) < 1e-6 for a, b, ca, cb in zip(times, times[1:], counts, counts[1:]))


def test_given_pty_links_are_where_the_emulator_serves(tmp_path):
    link = tmp_path / "serial-link"
    with ldoem.Emulator("minimal", transports=("serial",), serial=str(link), virtual_time=True) as emulator:
        assert emulator.device == emulator.serial and link.is_symlink()
        with ldoem.Scanner(f"serial:{link}") as scanner:
            assert scanner.status()["sensor"] == "IDLE"


def test_the_recording_shows_the_requests_the_device_refused():
    with ldoem.Emulator("minimal", virtual_time=True, record=True) as emulator:
        with ldoem.Scanner(emulator.device) as scanner:
            with pytest.raises(ldoem.ServiceFailure):
                scanner.measure()  # from IDLE (spec 5, D2 reason 3)
    assert [(code, reason) for _, code, reason in emulator.refusals()] == [(0x0404, 3)]  # TRANS_MEASURE


def test_stop_kills_a_daemon_that_does_not_answer():
    import os
    import signal
    import time
    emulator = ldoem.Emulator("minimal", virtual_time=True, stop_timeout=0.5).start()
    try:
        os.kill(emulator.process.pid, signal.SIGSTOP)  # neither quit nor SIGTERM can end it now
        started = time.monotonic()
        status = emulator.stop()
    finally:
        emulator.stop()
    assert status == -signal.SIGKILL
    assert time.monotonic() - started < 30
    assert not emulator.running
