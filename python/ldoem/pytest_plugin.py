"""pytest plugin of ldoem (entry point pytest11 `ldoem.pytest_plugin`, or `-p ldoem.pytest_plugin`).

Fixtures:
  ldoem_emulator   a started ldoem-emud (ldoem.Emulator), stopped after the test. Scene and
                   transport from @pytest.mark.ldoem_scene(scene, transports=("tcp",),
                   virtual_time=True, **Emulator options) or the `ldoem_scene` fixture (default
                   "minimal"); virtual time by default.
  ldoem_scenario   the fault scenario of this run (ldoem.faults.Scenario), or None.
Marks:
  @pytest.mark.ldoem_faults(transport="tcp", kinds=None, triggers=None)
                   runs the test once per fault scenario (ldoem.faults.scenarios), with ids such
                   as test_driver[tcp-power_cycle-while_streaming]; ldoem_emulator injects the
                   scenario's fault before the test starts. The scenario's outcome (the device's
                   events, whether profiles flowed again after the fault) is reported beside the
                   test's own: in a report section, as JUnit properties (--junitxml) and in the
                   terminal summary.
"""

import json

import pytest

from . import faults
from .emulator import Emulator

_OUTCOMES = pytest.StashKey()  # config: (nodeid, test outcome, Outcome) per scenario run
_ITEM_OUTCOME = pytest.StashKey()  # item: its scenario's Outcome
_TEST_OUTCOME = pytest.StashKey()  # item: the test's own outcome


def pytest_configure(config):
    config.addinivalue_line("markers", "ldoem_faults(transport='tcp', kinds=None, triggers=None): "
                                       "run the test once per ldoem fault scenario")
    config.addinivalue_line("markers", "ldoem_scene(scene, transports=('tcp',), virtual_time=True, **options): "
                                       "the ldoem-emud the ldoem_emulator fixture starts")
    config.stash[_OUTCOMES] = []


def pytest_generate_tests(metafunc):
    marker = metafunc.definition.get_closest_marker("ldoem_faults")
    if marker is None:
        return
    if "ldoem_scenario" not in metafunc.fixturenames:
        raise pytest.UsageError(f"{metafunc.definition.nodeid}: @pytest.mark.ldoem_faults needs the ldoem_emulator fixture")
    chosen = faults.scenarios(*marker.args, **marker.kwargs)
    metafunc.parametrize("ldoem_scenario", chosen, ids=[scenario.id for scenario in chosen], indirect=True)


@pytest.fixture
def ldoem_scenario(request):
    return getattr(request, "param", None)


@pytest.fixture
def ldoem_scene():
    """The scene ldoem_emulator runs (override this fixture or use @pytest.mark.ldoem_scene)."""
    return "minimal"


@pytest.fixture
def ldoem_emulator(request, ldoem_scenario, ldoem_scene):
    options = {"scene": ldoem_scene, "transports": ("tcp",), "virtual_time": True, "record": True}
    marker = request.node.get_closest_marker("ldoem_scene")
    if marker is not None:
        if marker.args:
            options["scene"] = marker.args[0]
        options.update(marker.kwargs)
    scenario = ldoem_scenario
    if scenario is not None and scenario.transport not in options["transports"]:
        options["transports"] = (scenario.transport,) + tuple(t for t in options["transports"] if t == "lpt")
    emulator = Emulator(**options).start()
    try:
        if scenario is not None:
            emulator.inject_fault(scenario.kind, **scenario.fault())
        yield emulator
        if scenario is not None:
            _report(request, faults.outcome_of(scenario, emulator))
    finally:
        emulator.stop()


def _report(request, outcome):
    item = request.node
    item.user_properties.append(("ldoem_scenario", outcome.scenario.id))
    item.user_properties.append(("ldoem_triggered", str(outcome.triggered).lower()))
    item.user_properties.append(("ldoem_device", outcome.device))
    item.user_properties.append(("ldoem_profiles_after_fault", str(outcome.profiles_after_fault)))
    item.user_properties.append(("ldoem_event_log", "\n".join(json.dumps(event) for event in outcome.events)))
    item.add_report_section("teardown", "ldoem scenario", outcome.summary() + "\n" +
                            "\n".join(json.dumps(event) for event in outcome.events))
    item.stash[_ITEM_OUTCOME] = outcome


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    result = yield
    report = result.get_result()
    if report.when == "call" or (report.when == "setup" and report.outcome != "passed"):
        item.stash[_TEST_OUTCOME] = report.outcome
    if report.when == "teardown" and _ITEM_OUTCOME in item.stash:
        item.config.stash[_OUTCOMES].append((item.nodeid, item.stash.get(_TEST_OUTCOME, "?"), item.stash[_ITEM_OUTCOME]))



def pytest_terminal_summary(terminalreporter, config):
    rows = config.stash.get(_OUTCOMES, [])
    if not rows:
        return
    terminalreporter.section("ldoem fault scenarios")
    for nodeid, test_outcome, outcome in rows:
        flow = ("profiles flowed again" if outcome.recovered else "no profile after the fault") if outcome.triggered \
            else "not triggered"
        terminalreporter.write_line(f"{test_outcome:7} {nodeid}: {outcome.device}; {flow}")
