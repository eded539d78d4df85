"""ldoem.faults' tables, which come from the emulator's catalogue (emulator/faults,
fault_kind.hpp, written into ldoem/_fault_catalogue.py at build time) rather than from a copy kept
in Python."""

from ldoem import faults
from ldoem._fault_catalogue import FAULT_CATALOGUE


def test_the_matrix_covers_the_catalogue_without_the_lpt_kinds():
    catalogue = {name: (fault_class, transports) for name, fault_class, transports, _ in FAULT_CATALOGUE}
    assert set(faults.DEVICE_KINDS) == {name for name, (fault_class, _) in catalogue.items() if fault_class == "device"}
    for name, (fault_class, transports) in catalogue.items():
        if fault_class == "wire" and transports != ("lpt",):
            assert faults.WIRE_KINDS[name] == transports
    assert "lpt_jam" not in faults.WIRE_KINDS and "lpt_lose_steps" not in faults.WIRE_KINDS


def test_kinds_keep_their_documented_order():
    # docs/python.md lists TCP's wire kinds in this order; docs/faults.md's Kinds table too.
    assert faults.kinds_for("tcp") == [
        "motor_stall", "motor_overspeed", "encoder_error", "power_cycle", "reset_spontaneous", "blind", "window_dirt",
        "drop_reply", "delay_reply", "duplicate_reply", "truncate_reply", "garbage", "corrupt_checksum", "tcp_reset",
        "tcp_stall", "bandwidth"]
    assert faults.WIRE_KINDS["corrupt_checksum"] == ("tcp", "serial")
    assert "isotp_bad_sn" in faults.kinds_for("can") and "corrupt_checksum" not in faults.kinds_for("can")


def test_every_parameter_row_names_a_kind_of_the_catalogue():
    # A kind renamed in the catalogue without its row here would silently lose its parameters.
    names = {name for name, *_ in FAULT_CATALOGUE}
    assert set(faults.PARAMETERS) <= names
    assert set(faults.FINAL_KINDS) <= set(faults.DEVICE_KINDS)


def test_an_unlisted_lasting_device_kind_lasts_one_second():
    # Every kind has its row today; what a new kind without one gets.
    kind = next(name for name, fault_class, _, one_shot in FAULT_CATALOGUE if fault_class == "device" and not one_shot)
    saved = faults.PARAMETERS.pop(kind)
    try:
        assert faults.Scenario("tcp", kind, "during_init").fault() == {
            "duration_s": 1, "on": {"service": "GET_STATUS", "nth": 1}}
        assert faults.Scenario("tcp", "drop_reply", "during_init").fault()["transport"] == "tcp"
    finally:
        faults.PARAMETERS[kind] = saved
