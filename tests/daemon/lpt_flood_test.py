#!/usr/bin/env python3
"""Issue 11 #6: a host that writes 4-byte register toggles to the LPT pty as fast as it can, with
the daemon in --virtual-time (the simulated clock stands still while input keeps coming), must not
grow the daemon's memory: the tilt history keeps at most two records per instant and a bounded
number overall. (Before the fix: +400 MiB for 24 MiB of toggles; 4.6 GB in 20 s in the report.)
Run with the ideal tilt motor and with motor_dynamics. Each flood is bounded in bytes (FLOOD_MIB)
and in wall time (FLOOD_LIMIT_S).
usage: lpt_flood_test.py EMUD SCENE"""
import os, signal, subprocess, sys, tempfile, time

FLOOD_MIB = 24          # written to the pty: 6 Mi toggles of 4 bytes (12 Mi steps)
FLOOD_LIMIT_S = 30.0    # stop writing after this much wall time whatever was written
MAX_GROWTH_MIB = 24     # RSS growth allowed over the flood (history cap: 2 MiB)

emud, scene_path = sys.argv[1:3]

def rss_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0

def flood(folder, scene, label):
    link = os.path.join(folder, "lpt")
    with tempfile.TemporaryFile() as err:
        daemon = subprocess.Popen([emud, "--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash",
                                   "--virtual-time", "--lpt", "lpt:pty:" + link, "--timeout", "120"],
                                  stdout=subprocess.PIPE, stderr=err, text=True,
                                  # Under ASan, freed memory waits in a 256 MiB quarantine by default.
                                  env=dict(os.environ, ASAN_OPTIONS="quarantine_size_mb=4"))
        try:
            for line in daemon.stdout:
                if line.strip() == "ready":
                    break
            before = rss_kib(daemon.pid)
            # DIR up + CLK rising, CLK low, DIR down + CLK rising, CLK low: one step up, one down.
            chunk = bytes([0x03, 0x01, 0x02, 0x00]) * 16384
            fd = os.open(link, os.O_WRONLY | os.O_NOCTTY)
            written = 0
            start = time.monotonic()
            peak = before
            while written < FLOOD_MIB * 1024 * 1024 and time.monotonic() - start < FLOOD_LIMIT_S:
                written += os.write(fd, chunk)
                peak = max(peak, rss_kib(daemon.pid))
            os.close(fd)
            time.sleep(0.5)
            peak = max(peak, rss_kib(daemon.pid))
            elapsed = time.monotonic() - start
            growth_mib = (peak - before) / 1024
            print(f"{label}: wrote {written / 1048576:.1f} MiB of register toggles in {elapsed:.1f} s; "
                  f"RSS {before / 1024:.1f} MiB -> peak {peak / 1024:.1f} MiB (+{growth_mib:.1f} MiB)")
            if daemon.poll() is not None:
                err.seek(0)
                sys.exit(f"{label}: ldoem-emud exited ({daemon.returncode}) during the flood:\n"
                         + err.read().decode(errors="replace"))
            if written < 4 * 1024 * 1024:
                sys.exit(f"{label}: less than 4 MiB written: the flood did not test anything")
            if growth_mib > MAX_GROWTH_MIB:
                sys.exit(f"{label}: RSS grew by {growth_mib:.1f} MiB (bound {MAX_GROWTH_MIB} MiB): per-input growth")
        finally:
            daemon.send_signal(signal.SIGTERM)
            try:
                daemon.wait(timeout=10)
            except subprocess.TimeoutExpired:
                daemon.kill()
                daemon.wait()

with tempfile.TemporaryDirectory() as folder:
    flood(folder, scene_path, "ideal motor")
    dynamic = os.path.join(folder, "dynamic.yaml")
    with open(scene_path) as f, open(dynamic, "w") as out:
        out.write(f.read() + "\neffects: [motor_dynamics]\n")
    flood(folder, dynamic, "motor_dynamics")
