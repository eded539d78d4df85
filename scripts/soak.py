"""The soak test behind scripts/soak.sh: starts the daemons, drives them for --duration seconds
with the clients of soak_clients.py, samples RSS, descriptors and CPU of every daemon once a
second, and checks the limits. Writes samples.csv and summary.txt into --out.

Processes (all on loopback, in a private temporary folder):
  emud-hub     ldoem-emud behind ldoem-hub: TCP scanner and LPT pty (device "lpt")
  emud-tcp     ldoem-emud that TCP clients connect to, stream from and drop
  emud-can     ldoem-emud on vcan0 behind ldoem-hub (device "can"), only where vcan0 exists
  ldoem-hub    16 clients; MOVEMOTOR steps go out on the LPT pty of emud-hub
Exit status 0 when every reply was right and the limits held, 1 otherwise, 2 on a setup error."""

import argparse
import os
import re
import signal
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import soak_clients as clients  # noqa: E402

RSS_LIMIT_KIB = 5 * 1024
HUB_CLIENTS = 16
TCP_STREAMERS = 4
START_TIMEOUT_S = 30


def fail_setup(message):
    print(f"soak: {message}", file=sys.stderr)
    sys.exit(2)


def wait_for(path, pattern, process, what):
    """Waits (bounded) until the file holds a line matching pattern; returns the match."""
    deadline = time.monotonic() + START_TIMEOUT_S
    while time.monotonic() < deadline:
        with open(path, encoding="utf-8", errors="replace") as log:
            for line in log.read().splitlines():
                match = re.search(pattern, line)
                if match:
                    return match
        if process.poll() is not None:
            break
        time.sleep(0.1)
    with open(path, encoding="utf-8", errors="replace") as log:
        fail_setup(f"{what} did not start (exit {process.poll()}): {log.read()[-2000:]}")


class Daemons:
    """Starts the processes, knows their pids, stops them at the end (bounded)."""

    def __init__(self, build, folder, duration, can):
        self.folder, self.processes, self.logs = folder, {}, {}
        emud = os.path.join(build, "emulator/daemon/ldoem-emud")
        hub = os.path.join(build, "driver/hub/ldoem-hub")
        for program in (emud, hub):
            if not os.access(program, os.X_OK):
                fail_setup(f"{program} not built (cmake --build --preset default)")
        common = ["--scene", "scenes/minimal.yaml", "--no-flash", "--timeout", str(duration + 120)]
        lpt = os.path.join(folder, "lpt")
        if os.path.lexists(lpt):  # a previous run's link into a pty that is gone
            os.unlink(lpt)
        self.start("emud-hub", [emud, *common, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--lpt", f"lpt:pty:{lpt}"])
        self.start("emud-tcp", [emud, *common, "--no-can", "--tcp", "tcp:127.0.0.1:0"])
        if can:
            self.start("emud-can", [emud, *common, "--can", "can:vcan0"])
        self.ports = {}
        for name in self.processes:
            wait_for(self.logs[name], r"^ready$", self.processes[name], name)
            match = re.search(r"^tcp 127\.0\.0\.1:(\d+)$", open(self.logs[name]).read(), re.M)
            if match:
                self.ports[name] = int(match.group(1))
        config = os.path.join(folder, "hub.yaml")
        with open(config, "w") as out:
            out.write("devices:\n  - name: lpt\n"
                      f"    scanner: tcp:127.0.0.1:{self.ports['emud-hub']}\n    lpt: lpt:pty:{lpt}\n")
            if can:
                out.write("  - name: can\n    scanner: can:vcan0\n")
        self.start("ldoem-hub", [hub, "--config", config, "--listen", "127.0.0.1:0"])
        match = wait_for(self.logs["ldoem-hub"], r"listening on 127\.0\.0\.1:(\d+)", self.processes["ldoem-hub"], "ldoem-hub")
        self.ports["ldoem-hub"] = int(match.group(1))

    def start(self, name, argv):
        self.logs[name] = os.path.join(self.folder, f"{name}.log")
        with open(self.logs[name], "w") as log:
            self.processes[name] = subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)

    def counters(self, name):
        """SIGUSR1 makes ldoem-emud print its counters; returns them as a dict."""
        size = os.path.getsize(self.logs[name])
        self.processes[name].send_signal(signal.SIGUSR1)
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            with open(self.logs[name]) as log:
                log.seek(size)
                match = re.search(r"counters: (.*)", log.read())
            if match:
                return {k: int(v) for k, v in (pair.split("=") for pair in match.group(1).split())}
            time.sleep(0.1)
        return {}

    def stop(self):
        """SIGTERM, then SIGKILL after 10 s; returns {name: exit status}."""
        for process in self.processes.values():
            if process.poll() is None:
                process.terminate()
        status = {}
        for name, process in self.processes.items():
            try:
                status[name] = process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
                status[name] = f"killed after 10 s ({process.wait()})"
        return status


def sample(pid):
    """(RSS KiB, open descriptors, CPU seconds used so far) of a live process."""
    with open(f"/proc/{pid}/status") as status:
        rss = int(re.search(r"^VmRSS:\s+(\d+)", status.read(), re.M).group(1))
    descriptors = len(os.listdir(f"/proc/{pid}/fd"))
    with open(f"/proc/{pid}/stat") as stat:
        fields = stat.read().rsplit(")", 1)[1].split()
    cpu = (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    return rss, descriptors, cpu


def descriptors_of(daemons):
    """{name: sorted list of what each open descriptor points at}."""
    result = {}
    for name, process in daemons.processes.items():
        folder = f"/proc/{process.pid}/fd"
        targets = []
        for fd in os.listdir(folder):
            try:
                targets.append(os.readlink(os.path.join(folder, fd)))
            except OSError:
                pass
        result[name] = sorted(re.sub(r"\[\d+\]", "[]", t) for t in targets)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--duration", type=int, default=600)
    parser.add_argument("--warmup", type=int, help="seconds before the RSS reference (default: a quarter of the run, at most 60)")
    parser.add_argument("--build-dir", default="build/default")
    parser.add_argument("--can", choices=("auto", "on", "off"), default="auto")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    if args.duration < 10:
        fail_setup("--duration must be at least 10 s")
    warmup = args.warmup if args.warmup is not None else min(60, args.duration // 4)
    can = args.can == "on" or (args.can == "auto" and os.path.exists("/sys/class/net/vcan0"))
    os.makedirs(args.out, exist_ok=True)
    folder = args.out  # logs, the hub configuration and the LPT pty link
    daemons = Daemons(args.build_dir, folder, args.duration, can)
    failures, tally = clients.Failures(), clients.Tally()
    devices = ["lpt", "can"] if can else ["lpt"]
    try:
        reference = clients.put_in_measure(daemons.ports["emud-tcp"])
        setup = clients.HubConnection(daemons.ports["ldoem-hub"])
        for device in devices:
            for step, command in enumerate(("INITIALIZE", "ROTATE", "MEASURE")):
                setup.request(f"setup{step}", device, command)
        setup.request("tilt1", "lpt", "MOVEMOTOR 1 up half")  # opens the LPT port
        if setup.request("tilt0", "lpt", "MOVEMOTOR 1 down half")["tilt_half_steps"] != "0":
            raise ValueError("the tilt does not start at 0")
        setup.close()
    except (OSError, ValueError, EOFError) as error:
        daemons.stop()
        fail_setup(f"setting the devices up failed: {error}")
    time.sleep(1)
    idle_before = descriptors_of(daemons)
    lpt_steps_before = daemons.counters("emud-hub").get("lpt_steps", 0)

    started = time.monotonic()
    deadline = started + args.duration
    threads = [threading.Thread(target=clients.hub_client, args=(daemons.ports["ldoem-hub"], devices, "lpt", deadline, n, failures, tally))
               for n in range(HUB_CLIENTS)]
    threads += [threading.Thread(target=clients.tcp_streamer, args=(daemons.ports["emud-tcp"], reference, deadline, 100 + n, failures, tally))
                for n in range(TCP_STREAMERS)]
    for thread in threads:
        thread.start()
    names = list(daemons.processes)
    rows, previous_cpu = [], {}
    while time.monotonic() < deadline:
        now = time.monotonic() - started
        row = [round(now, 1)]
        for name in names:
            try:
                rss, fds, cpu = sample(daemons.processes[name].pid)
            except (OSError, AttributeError):
                failures.add(f"{name} is gone (exit {daemons.processes[name].poll()})")
                rss, fds, cpu = 0, 0, previous_cpu.get(name, (0, 0))[0]
            last_cpu, last_time = previous_cpu.get(name, (cpu, now - 1))
            row += [rss, fds, round(100 * (cpu - last_cpu) / max(now - last_time, 1e-3), 1)]
            previous_cpu[name] = (cpu, now)
        rows.append(row)
        time.sleep(max(0.0, min(1.0, deadline - time.monotonic())))
    for thread in threads:
        thread.join(timeout=clients.IO_TIMEOUT_S * 3)
        if thread.is_alive():
            failures.add("a client did not finish within 30 s of the end")

    # The moves balanced: one more half step up must report position 1 (tilt0 said 0).
    try:
        final = clients.HubConnection(daemons.ports["ldoem-hub"])
        position = final.request("end1", "lpt", "MOVEMOTOR 1 up half")["tilt_half_steps"]
        final.request("end2", "lpt", "MOVEMOTOR 1 down half")
        final.close()
        if position != "1":
            failures.add(f"tilt after the balanced moves plus one half step is {position}, not 1")
    except (OSError, ValueError, EOFError, KeyError) as error:
        failures.add(f"final tilt check: {error}")
    time.sleep(0.5)  # the last pulses may still be in the pty
    moved = tally.values.get("half_steps", 0) + 2
    counters = daemons.counters("emud-hub")
    lpt_steps = counters.get("lpt_steps", 0) - lpt_steps_before
    if lpt_steps != moved:
        failures.add(f"emud-hub saw {lpt_steps} LPT steps, the hub moved {moved}")
    for name in names:
        if name.startswith("emud"):
            seen = daemons.counters(name)
            for counter in ("framing_errors", "tcp_dropped_slow", "isotp_receive_errors", "isotp_send_failures"):
                if seen.get(counter, 0):
                    failures.add(f"{name}: {counter}={seen[counter]}")
    time.sleep(2)
    idle_after = descriptors_of(daemons)
    exits = daemons.stop()

    limits = []
    for index, name in enumerate(names):
        series = [(row[0], row[1 + 3 * index], row[2 + 3 * index]) for row in rows]
        after = [s for s in series if s[0] >= warmup]
        if not after:
            failures.add("no sample after the warm-up")
            continue
        reference_rss, peak = after[0][1], max(s[1] for s in after)
        growth = peak - reference_rss
        limits.append(f"{name}: RSS {reference_rss / 1024:.1f} MiB at {after[0][0]:.0f} s, peak after {peak / 1024:.1f} MiB "
                      f"(+{growth / 1024:.2f} MiB, limit +5); descriptors idle {len(idle_before[name])} before, {len(idle_after[name])} after, "
                      f"{min(s[2] for s in series)}..{max(s[2] for s in series)} while loaded")
        if growth > RSS_LIMIT_KIB:
            failures.add(f"{name}: RSS grew {growth / 1024:.2f} MiB after the warm-up")
        if idle_after[name] != idle_before[name]:
            failures.add(f"{name}: descriptors idle before the load {idle_before[name]}, after {idle_after[name]}")
    for name, status in exits.items():
        if status != -signal.SIGTERM and status != 128 + signal.SIGTERM:
            failures.add(f"{name}: exit status {status} after SIGTERM")

    with open(os.path.join(args.out, "samples.csv"), "w") as csv:
        csv.write("seconds," + ",".join(f"{n}_rss_kib,{n}_fds,{n}_cpu_percent" for n in names) + "\n")
        for row in rows:
            csv.write(",".join(str(v) for v in row) + "\n")
    cpu_means = [f"{name} {sum(r[3 + 3 * i] for r in rows[1:]) / max(len(rows) - 1, 1):.1f} %" for i, name in enumerate(names)]
    summary = [f"duration {args.duration} s, warm-up {warmup} s, CAN {'on vcan0' if can else 'off (no vcan0)'}",
               f"{HUB_CLIENTS} hub clients, {TCP_STREAMERS} TCP streamers; " + ", ".join(f"{k} {v}" for k, v in sorted(tally.values.items())),
               "mean CPU: " + ", ".join(cpu_means), *limits,
               f"failures: {failures.count}", *failures.messages]
    with open(os.path.join(args.out, "summary.txt"), "w") as out:
        out.write("\n".join(summary) + "\n")
    print("\n".join(summary))
    print(f"soak: {'PASSED' if failures.count == 0 else 'FAILED'} (samples and logs in {args.out})")
    return 0 if failures.count == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
