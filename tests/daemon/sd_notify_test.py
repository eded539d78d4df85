#!/usr/bin/env python3
"""ldoem-emud and ldoem-hub under a stand-in for systemd: each must send READY=1 once it serves
and WATCHDOG=1 at half the WATCHDOG_USEC period from its loop (Type=notify units, docs/service.md).
usage: sd_notify_test.py EMUD HUB SCENE"""
import os, socket, subprocess, sys, tempfile, time

def messages_from(command, seconds, folder, env_extra=None):
    path = os.path.join(folder, "notify")
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(path)
    sock.settimeout(0.1)
    env = dict(os.environ, NOTIFY_SOCKET=path, WATCHDOG_USEC="200000", **(env_extra or {}))
    process = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    got = []
    end = time.monotonic() + seconds
    try:
        while time.monotonic() < end:
            try:
                got.extend(sock.recv(4096).decode().split("\n"))
            except socket.timeout:
                pass
    finally:
        process.terminate()
        process.wait(timeout=20)
        sock.close()
        os.unlink(path)
    return got, process.returncode

def check(name, got):
    ready = sum(1 for m in got if m == "READY=1")
    pings = sum(1 for m in got if m == "WATCHDOG=1")
    # 1.5 s at one ping per 100 ms: about 15; 5 leaves room for a loaded machine.
    if ready != 1 or pings < 5:
        sys.exit(f"{name}: READY=1 x{ready}, WATCHDOG=1 x{pings} (want 1 and >= 5): {got}")
    print(f"{name}: READY=1 once, WATCHDOG=1 x{pings} in 1.5 s")

emud, hub, scene = sys.argv[1:4]
with tempfile.TemporaryDirectory() as folder:
    got, _ = messages_from([emud, "--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash",
                            "--timeout", "30"], 1.5, folder)
    check("ldoem-emud", got)
    config = os.path.join(folder, "hub.yaml")
    with open(config, "w") as f:
        f.write("listen: 127.0.0.1:0\ndevices:\n  - name: d\n    scanner: tcp:127.0.0.1:1\n")
    got, _ = messages_from([hub, "--config", config], 1.5, folder)
    check("ldoem-hub", got)
