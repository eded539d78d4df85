#!/usr/bin/env python3
"""Profiles per second through Python (ldoem.Scanner.profiles) against the C++ client
(ldoem-latency --profiles) on the same stream, taking turns in one run; and the paper's
9801-point scan to numpy (ldoem.scan). Writes the table into docs/python.md with --write-doc.

    PYTHONPATH=build/default/python /usr/bin/python3 scripts/bench-python.py [--seconds 3] [--rounds 3]
        [--latency build/default/tools/latency/ldoem-latency] [--write-doc]

The stream: a wall 5 m ahead, the flash at 20 Hz and 0.5 deg (scripts/lib/latency-daemon.sh's
scene), GET_PROFILE 0000 39FF over TCP, the daemon in virtual time: it streams as fast as the host
takes the profiles (D10 skips what the host is too slow for), so profiles/s is the host's rate.
"""

import argparse
import os
import re
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

import ldoem

ROOT = Path(__file__).resolve().parent.parent
SCENE = {"scanner": {"flash": {"motor_speed_hz": 20, "angle_step_ticks": 8}},
         "objects": [{"name": "wall", "box": {"size_m": [0.2, 20, 6]}, "pose": {"position_m": [5.1, 0, 0]},
                      "reflectance": 0.8}]}


def python_rate(seconds):
    with ldoem.Emulator(SCENE, virtual_time=True) as emulator, ldoem.Scanner(emulator.device) as scanner:
        scanner.rotate()
        scanner.measure()
        count = points = 0
        cpu = time.process_time()
        with scanner.profiles(format=ldoem.FORMAT_RANGE) as stream:
            start = time.monotonic()
            end = start + seconds
            for profile in stream:
                count += 1
                points += len(profile.points)
                if time.monotonic() >= end:
                    break
            elapsed = time.monotonic() - start
        cpu = time.process_time() - cpu
    return count / elapsed, points / max(count, 1), cpu / max(count, 1)


def cpp_rate(latency, seconds):
    with ldoem.Emulator(SCENE, virtual_time=True) as emulator:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        out = subprocess.run([latency, "--tcp", emulator.device[len("tcp:"):], "--profiles", str(seconds), "--format",
                              "39ff"], capture_output=True, text=True, timeout=seconds + 60, check=True).stdout
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    rate = float(re.search(r"profiles_per_s=([0-9.]+)", out).group(1))
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return rate, cpu / max(rate * seconds, 1)


def scan_time():
    with ldoem.Emulator("corridor", transports=("tcp", "lpt"), virtual_time=True) as emulator:
        start = time.monotonic()
        cloud = ldoem.scan(emulator.device, emulator.lpt)
        return time.monotonic() - start, cloud


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--latency", default=str(ROOT / "build/default/tools/latency/ldoem-latency"))
    parser.add_argument("--write-doc", action="store_true")
    options = parser.parse_args()
    load_before = os.getloadavg()[0]
    py, cpp, py_cpu, cpp_cpu = [], [], [], []
    points = 0
    for _ in range(options.rounds):
        rate, points, cpu = python_rate(options.seconds)
        py.append(rate)
        py_cpu.append(cpu)
        rate, cpu = cpp_rate(options.latency, options.seconds)
        cpp.append(rate)
        cpp_cpu.append(cpu)
    scan_seconds, cloud = scan_time()
    ratio = statistics.median(py) / statistics.median(cpp)
    lines = [
        f"Profiles/s on the same stream ({options.rounds} rounds of {options.seconds:g} s each, taking turns; medians):",
        "",
        "| client | profiles/s (median) | each round | client CPU per profile (us, median) |",
        "|---|---|---|---|",
        f"| C++ (ldoem-latency --profiles, raw TCP telegrams) | {statistics.median(cpp):.0f} | "
        + ", ".join(f"{r:.0f}" for r in cpp) + f" | {statistics.median(cpp_cpu) * 1e6:.1f} |",
        f"| Python (`for p in scanner.profiles()`, {points:.0f} points a profile to numpy) | {statistics.median(py):.0f} | "
        + ", ".join(f"{r:.0f}" for r in py) + f" | {statistics.median(py_cpu) * 1e6:.1f} |",
        "",
        f"Python / C++: {ratio:.3f}.",
        "",
        f"ldoem.scan of the corridor (9801 points, virtual time): {scan_seconds:.2f} s wall, an array of "
        f"{cloud.nbytes} bytes that numpy owns (`owndata` {cloud.flags.owndata}, base {cloud.base}): the cloud is copied "
        "once, from libldoem's point cloud into the rows.",
        "",
        f"Machine: {os.cpu_count()} CPUs, load average {load_before:.2f} before and {os.getloadavg()[0]:.2f} after the run.",
    ]
    text = "\n".join(lines)
    print(text)
    if options.write_doc:
        doc = ROOT / "docs/python.md"
        content = doc.read_text()
        begin, end = "<!-- bench-python: begin -->", "<!-- bench-python: end -->"
        head, _, rest = content.partition(begin)
        _, _, tail = rest.partition(end)
        doc.write_text(head + begin + "\n<!-- written by scripts/bench-python.py --write-doc: do not edit by hand -->\n"
                       + text + "\n" + end + tail)
    return 0


if __name__ == "__main__":
    sys.exit(main())
