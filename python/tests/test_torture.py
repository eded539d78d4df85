"""python3 -m ldoem.torture on ldoem-scan (with and without retries) and on a naive client: the
naive client and ldoem-scan --retries 0 fail the power cycle and the dropped reply mid-stream,
ldoem-scan with retries passes them; the outputs are there and readable."""

import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
SCENARIOS = ["--kinds", "power_cycle,drop_reply", "--triggers", "while_streaming,during_init"]


def torture(out, *command):
    process = subprocess.run([sys.executable, "-m", "ldoem.torture", *SCENARIOS, "--time-limit", "60", "--out", str(out),
                              "--", *command], capture_output=True, text=True, timeout=900)
    verdicts = {}
    for case in ET.parse(out / "junit.xml").getroot().iter("testcase"):
        properties = {p.get("name"): p.get("value") for p in case.iter("property")}
        verdicts[case.get("name")] = (case.find("failure") is None, properties["verdict"])
    assert (out / "matrix.png").stat().st_size > 1000
    assert "| `power_cycle` |" in (out / "matrix.md").read_text()
    return process, verdicts


def scan_command(tmp_path, retries):
    scan = os.environ.get("LDOEM_SCAN", "ldoem-scan")
    return [scan, "--device", "{device}", "--lpt", "{lpt}", "--out", str(tmp_path / "cloud.pcd"), "--vertical-apex",
            "0.36", "--timeout", "1", "--retries", str(retries)]


def test_naive_client_fails_the_power_cycle_and_the_dropped_reply(tmp_path):
    process, verdicts = torture(tmp_path / "naive", sys.executable, str(HERE / "naive_client.py"), "{device}")
    assert process.returncode == 1, process.stdout + process.stderr
    for scenario in ("tcp-power_cycle-while_streaming", "tcp-drop_reply-while_streaming", "tcp-drop_reply-during_init"):
        assert verdicts[scenario] == (False, "failed"), (scenario, verdicts)


@pytest.mark.parametrize("retries", [0, 3])
def test_ldoem_scan_passes_them_with_retries_and_fails_without(tmp_path, retries):
    process, verdicts = torture(tmp_path / f"scan-{retries}", *scan_command(tmp_path, retries))
    if retries:
        assert process.returncode == 0, process.stdout + process.stderr
        assert all(passed for passed, _ in verdicts.values()), verdicts
        assert verdicts["tcp-power_cycle-while_streaming"] == (True, "recovered")
    else:
        assert process.returncode == 1
        assert verdicts["tcp-drop_reply-while_streaming"] == (False, "failed"), verdicts
        assert verdicts["tcp-power_cycle-while_streaming"] == (False, "failed"), verdicts


def test_a_command_that_hangs_is_killed_at_the_time_limit(tmp_path):
    out = tmp_path / "hang"
    process = subprocess.run([sys.executable, "-m", "ldoem.torture", "--kinds", "drop_reply", "--triggers", "during_init",
                              "--time-limit", "1", "--out", str(out), "--", "sleep", "30"],
                             capture_output=True, text=True, timeout=120)
    assert process.returncode == 1
    assert "hung" in (out / "matrix.md").read_text()


def test_usage_errors_exit_2():
    process = subprocess.run([sys.executable, "-m", "ldoem.torture", "--kinds", "no_such_kind", "--", "true"],
                             capture_output=True, text=True, timeout=60)
    assert process.returncode == 2 and "no_such_kind" in process.stderr
