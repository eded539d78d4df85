#!/usr/bin/env python3
"""Issue 27 (D8): add-object imported its mesh on the event loop's thread, so every host went
unanswered for the whole import (657 ms for the project's own large-rock.obj, 13.2 s for a lying
STL header). Now the import runs on a worker thread and the reply comes when it is done.

The test judges order, not time: it asks add-object for a mesh that takes seconds to import, then
at once sends GET_STATUS over TCP. Before the fix the loop was busy importing, so the add-object
reply was written before the TCP request was even read: when the TCP reply arrives, the control
reply is already there. After it, the TCP reply comes while the import still runs. Bounded: every
wait has a timeout, the daemon is killed at the end.
usage: add_object_off_loop_test.py EMUD SCENE"""
import json, os, select, socket, subprocess, sys, tempfile, time

emud, scene = sys.argv[1:3]
GET_STATUS = bytes.fromhex("02555350000000020102 03".replace(" ", ""))
LIMIT_S = 60

def write_mesh(path, rings=400, segments=400):  # a closed sphere of 2 * rings * segments triangles
    import math
    with open(path, "w") as f:
        for i in range(rings + 1):
            lat = math.pi * i / rings
            for j in range(segments):
                lon = 2 * math.pi * j / segments
                f.write(f"v {math.sin(lat) * math.cos(lon):.6f} {math.sin(lat) * math.sin(lon):.6f} {math.cos(lat):.6f}\n")
        for i in range(rings):
            for j in range(segments):
                a = i * segments + j + 1
                b = i * segments + (j + 1) % segments + 1
                f.write(f"f {a} {b} {a + segments}\nf {b} {b + segments} {a + segments}\n")

pending = []  # lines read from the control socket, not yet used

def read_lines(sock, wait_s):
    """Reads what arrives within wait_s (0: only what is there) into `pending`."""
    data = b""
    deadline = time.time() + wait_s
    while True:
        if not select.select([sock], [], [], max(0.0, deadline - time.time()))[0]:
            break
        chunk = sock.recv(65536)
        if not chunk:
            sys.exit("control socket closed")
        data += chunk
        if data.endswith(b"\n"):
            break
    pending.extend(json.loads(line) for line in data.decode().splitlines() if line.strip())

def reply(sock, deadline):
    """The next line that is not an event (events go to every client at any time)."""
    while True:
        for i, line in enumerate(pending):
            if "event" not in line:
                return pending.pop(i)
        if time.time() > deadline:
            sys.exit("no reply from the control socket in time")
        read_lines(sock, max(0.0, deadline - time.time()))

with tempfile.TemporaryDirectory() as folder:
    mesh = os.path.join(folder, "big.obj")
    write_mesh(mesh)
    control = os.path.join(folder, "ctl.sock")
    daemon = subprocess.Popen([emud, "--scene", scene, "--no-can", "--tcp", "127.0.0.1:0", "--no-flash",
                               "--control", control, "--timeout", str(LIMIT_S)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        port = None
        deadline = time.time() + 30
        while time.time() < deadline:
            line = daemon.stdout.readline()
            if not line:
                sys.exit("ldoem-emud ended before ready: " + daemon.stderr.read())
            if line.startswith("tcp "):
                port = int(line.split(":")[-1])
            if line.strip() == "ready":
                break
        ctl = socket.socket(socket.AF_UNIX)
        ctl.connect(control)
        read_lines(ctl, 10)  # greeting
        pending.clear()
        host = socket.create_connection(("127.0.0.1", port), timeout=10)
        request = {"execute": "add-object", "id": 1,
                   "arguments": {"object": {"name": "big", "mesh": {"file": mesh}, "pose": {"position_m": [30, 0, 0]}}}}
        ctl.sendall((json.dumps(request) + "\n").encode())
        time.sleep(0.05)  # the daemon has read the line and started the import
        host.sendall(GET_STATUS)
        status_reply = b""
        while len(status_reply) < 8 or len(status_reply) < 8 + int.from_bytes(status_reply[4:8], "big") + 1:
            chunk = host.recv(65536)
            if not chunk:
                sys.exit("TCP connection closed before the GET_STATUS reply")
            status_reply += chunk
        read_lines(ctl, 0)
        early = [line for line in pending if line.get("id") == 1]
        print(f"GET_STATUS answered ({len(status_reply)} bytes); add-object reply already there: {bool(early)}")
        if early:
            sys.exit(f"the add-object reply {early[0]} came before GET_STATUS was answered: the import ran on the loop")
        answer = reply(ctl, time.time() + LIMIT_S)
        print("add-object:", answer)
        if answer.get("id") != 1 or "return" not in answer or answer["return"].get("name") != "big":
            sys.exit(f"unexpected add-object reply: {answer}")
        # The control session goes on in order after the deferred reply.
        ctl.sendall(b'{"execute": "query-status", "id": 2}\n')
        status = reply(ctl, time.time() + 10)
        if status.get("id") != 2:
            sys.exit(f"unexpected reply after add-object: {status}")
    finally:
        daemon.kill()
        daemon.wait()
