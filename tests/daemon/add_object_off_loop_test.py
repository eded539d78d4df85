#!/usr/bin/env python3
"""Issue 27 (D8): add-object imported its mesh on the event loop's thread, so every host went
unanswered for the whole import (657 ms for the project's own large-rock.obj, 13.2 s for a lying
STL header). Now the import runs on a worker thread and the reply comes when it is done.

The test judges order, not time: it asks add-object for a mesh that takes seconds to import, then
at once sends GET_STATUS over TCP. Before the fix the loop was busy importing, so the add-object
reply was written before the TCP request was even read: when the TCP reply arrives, the control
reply is already there. After it, the TCP reply comes while the import still runs. Bounded: every
wait has a timeout, the daemon is killed at the end.

The mesh's collision tree (ODE's OPCODE trimesh data) is built on the worker too: it had stalled
the hosts 217-336 ms for large-rock.obj once the import had moved. query-status counts the trees
the loop built at world changes (mesh_trees_built_on_loop): 0 after the add-object, and after a
remove-object (whose rebuilt index reuses the tree). That the counter sees a tree built on the
loop is checked under --virtual-time, where the import and the tree stay on the loop.
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

def start(folder, extra):
    """ldoem-emud on minimal.yaml with a control socket: (process, TCP port, control socket)."""
    control = os.path.join(folder, "ctl.sock")
    if os.path.exists(control):
        os.unlink(control)
    daemon = subprocess.Popen([emud, "--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash",
                               "--control", control, "--timeout", str(LIMIT_S)] + extra,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    port = None
    deadline = time.time() + 30
    while time.time() < deadline:
        line = daemon.stdout.readline()
        if not line:
            daemon.kill()
            sys.exit("ldoem-emud ended before ready: " + daemon.stderr.read())
        if line.startswith("tcp "):
            port = int(line.split(":")[-1])
        if line.strip() == "ready":
            break
    ctl = socket.socket(socket.AF_UNIX)
    ctl.connect(control)
    read_lines(ctl, 10)  # greeting
    pending.clear()
    return daemon, port, ctl

def ask(ctl, request):
    ctl.sendall((json.dumps(request) + "\n").encode())
    answer = reply(ctl, time.time() + LIMIT_S)
    if answer.get("id") != request["id"] or "return" not in answer:
        sys.exit(f"unexpected reply to {request}: {answer}")
    return answer["return"]

def trees_on_loop(ctl, id):
    return ask(ctl, {"execute": "query-status", "id": id})["counters"]["mesh_trees_built_on_loop"]

with tempfile.TemporaryDirectory() as folder:
    mesh = os.path.join(folder, "big.obj")
    write_mesh(mesh)
    daemon, port, ctl = start(folder, [])
    try:
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
        # The control session goes on in order after the deferred reply; the mesh's tree was
        # built by the worker, and the remove-object's rebuilt index builds none either.
        built = trees_on_loop(ctl, 2)
        print("mesh trees built on the loop after add-object:", built)
        if built != 0:
            sys.exit(f"the loop built {built} mesh tree(s) for add-object: the tree was not built on the worker")
        ask(ctl, {"execute": "remove-object", "id": 3, "arguments": {"name": "big"}})
        built = trees_on_loop(ctl, 4)
        print("mesh trees built on the loop after remove-object:", built)
        if built != 0:
            sys.exit(f"the loop built {built} mesh tree(s) for remove-object: the index did not reuse the tree")
    finally:
        daemon.kill()
        daemon.wait()

    # The counter can fail: under --virtual-time the import and its tree stay on the loop.
    small = os.path.join(folder, "small.obj")
    write_mesh(small, rings=4, segments=6)
    daemon, port, ctl = start(folder, ["--virtual-time"])
    try:
        ask(ctl, {"execute": "add-object", "id": 1,
                  "arguments": {"object": {"name": "small", "mesh": {"file": small}, "pose": {"position_m": [30, 0, 0]}}}})
        built = trees_on_loop(ctl, 2)
        print("under --virtual-time, mesh trees built on the loop:", built)
        if built != 1:
            sys.exit(f"under --virtual-time the loop built {built} mesh trees, expected 1")
    finally:
        daemon.kill()
        daemon.wait()
