"""The pytest plugin from a user's side: a test file with @pytest.mark.ldoem_faults run in its
own pytest (pytester), the plugin found through the package's pytest11 entry point."""

import xml.etree.ElementTree as ET

pytest_plugins = ["pytester"]

DRIVER_TEST = '''
import pytest
import ldoem

@pytest.mark.ldoem_faults("tcp", kinds=["power_cycle", "drop_reply"], triggers=["during_init", "while_streaming"])
def test_driver(ldoem_emulator, ldoem_scenario):
    # A driver with no retry: a lost reply or connection fails the test.
    with ldoem.Scanner(ldoem_emulator.device, request_timeout=0.5) as scanner:
        scanner.rotate()
        scanner.measure()
        with scanner.profiles(count=5, timeout=1.0) as stream:
            assert len(list(stream)) == 5

def test_plain(ldoem_emulator, ldoem_scenario):
    assert ldoem_scenario is None
    with ldoem.Scanner(ldoem_emulator.device) as scanner:
        assert scanner.status()["sensor"] == "IDLE"
'''


def run(pytester, *args):
    pytester.makepyfile(test_driver=DRIVER_TEST)
    return pytester.runpytest_subprocess("-p", "no:cacheprovider", "--junitxml=matrix.xml", "-v", *args, timeout=300)


def junit_cases(pytester):
    root = ET.parse(pytester.path / "matrix.xml").getroot()
    cases = {}
    for case in root.iter("testcase"):
        properties = {p.get("name"): p.get("value") for p in case.iter("property")}
        cases[case.get("name")] = (case.find("failure") is not None, properties)
    return cases


def test_the_matrix_has_readable_ids_outcomes_and_junit(pytester):
    result = run(pytester)
    result.stdout.fnmatch_lines([
        "*test_driver[[]tcp-power_cycle-during_init[]]*",
        "*test_driver[[]tcp-power_cycle-while_streaming[]]*",
        "*test_driver[[]tcp-drop_reply-during_init[]]*",
        "*test_driver[[]tcp-drop_reply-while_streaming[]]*",
        "*ldoem fault scenarios*",
    ])
    cases = junit_cases(pytester)
    assert set(cases) == {"test_driver[tcp-power_cycle-during_init]", "test_driver[tcp-power_cycle-while_streaming]",
                          "test_driver[tcp-drop_reply-during_init]", "test_driver[tcp-drop_reply-while_streaming]",
                          "test_plain"}
    failed, properties = cases["test_driver[tcp-power_cycle-while_streaming]"]
    assert failed, "a driver without reconnect survived a power cycle mid-stream"
    assert properties["ldoem_scenario"] == "tcp-power_cycle-while_streaming"
    assert properties["ldoem_triggered"] == "true"
    assert "POWER_OFF" in properties["ldoem_device"]
    assert "FAULT_INJECTED" in properties["ldoem_event_log"]
    failed, properties = cases["test_driver[tcp-drop_reply-during_init]"]
    assert failed and properties["ldoem_triggered"] == "true"
    assert cases["test_plain"] == (False, {})


def test_naming_the_plugin_with_p_as_well_does_not_load_it_twice(pytester):
    result = run(pytester, "-p", "ldoem.pytest_plugin", "-k", "test_plain")
    result.assert_outcomes(passed=1, deselected=4)
