#!/usr/bin/env python3
"""Issue 11 #1: ldoem-emud with RLIMIT_NOFILE 64 and 80 TCP connections must not spin on
accept(): few warnings on stderr, little CPU, and a prompt exit on SIGTERM. (Before the fix: 1.88 million warnings in 3 s at full CPU.)
usage: fd_exhaustion_test.py EMUD SCENE"""
import os, resource, signal, socket, subprocess, sys, tempfile, time

emud, scene = sys.argv[1:3]
def limit():
    resource.setrlimit(resource.RLIMIT_NOFILE, (64, 64))
with tempfile.TemporaryFile() as err:
    daemon = subprocess.Popen([emud, "--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash",
                               "--timeout", "60"], stdout=subprocess.PIPE, stderr=err, preexec_fn=limit, text=True)
    port = None
    for line in daemon.stdout:
        if line.startswith("tcp "):
            port = int(line.rsplit(":", 1)[1])
        if line.strip() == "ready":
            break
    clients = []
    for i in range(80):  # non-blocking, in batches that fit the listen backlog
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        s.setblocking(False)
        s.connect_ex(("127.0.0.1", port))
        clients.append(s)
        if i % 8 == 7:
            time.sleep(0.1)
    time.sleep(2.0)
    with open(f"/proc/{daemon.pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    cpu_s = (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    daemon.send_signal(signal.SIGTERM)
    start = time.monotonic()
    try:
        daemon.wait(timeout=10)
    except subprocess.TimeoutExpired:
        daemon.kill()
        sys.exit("ldoem-emud did not exit within 10 s of SIGTERM")
    stop_s = time.monotonic() - start
    err.seek(0)
    log = err.read().decode(errors="replace")
    warnings = sum(1 for l in log.splitlines() if "Too many open files" in l)
    print(f"accept warnings: {warnings}, CPU in 2 s: {cpu_s:.2f} s, exit after SIGTERM: {stop_s:.2f} s")
    if warnings > 3:
        sys.exit(f"{warnings} accept warnings (rate limit: one per 10 s)")
    if cpu_s > 1.0:
        sys.exit(f"the daemon used {cpu_s:.2f} s of CPU in 2 s: it spins")
    if "not accepting" not in log:
        sys.exit("the daemon never ran out of descriptors: the test did not test anything\n" + log)
