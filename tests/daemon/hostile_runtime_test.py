#!/usr/bin/env python3
"""Issue 27, the runtime half: each case reproduces one defect against ldoem-emud and checks
that it now gives a clear error or a bounded result. Every wait is bounded; memory is read from
/proc/PID/status (VmHWM), never judged against wall-clock time.
usage: hostile_runtime_test.py CASE EMUD SCENE [REPLAY]
cases: delay_reply garbage control_fd_exhaustion record_files record_full_disk event_log_full
       identification listen_backlog"""
import json, os, resource, select, signal, socket, struct, subprocess, sys, tempfile, time

GET_STATUS = bytes.fromhex("02555350000000020102 03".replace(" ", ""))


def frame(payload):
    x = 0
    for b in payload:
        x ^= b
    return b"\x02USP" + struct.pack(">I", len(payload)) + payload + bytes([x])


class Daemon:
    """ldoem-emud on a free loopback port; stderr kept in a file; stopped by stop()."""

    def __init__(self, emud, scene, extra=(), preexec=None, control=None, expect_start=True):
        self.err = tempfile.TemporaryFile()
        args = [emud, "--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash", "--timeout", "120"]
        if control:
            args += ["--control", control]
        self.proc = subprocess.Popen(args + list(extra), stdout=subprocess.PIPE, stderr=self.err,
                                     preexec_fn=preexec, text=True)
        self.port = None
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            ready, _, _ = select.select([self.proc.stdout], [], [], 1.0)
            if not ready:
                continue
            line = self.proc.stdout.readline()
            if not line:
                break
            if line.startswith("tcp "):
                self.port = int(line.rsplit(":", 1)[1])
            if line.strip() == "ready":
                break
        if expect_start and self.port is None:
            self.stop()
            sys.exit("ldoem-emud did not start:\n" + self.log())

    def hwm_kib(self):
        with open(f"/proc/{self.proc.pid}/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
        return 0

    def cpu_s(self):
        with open(f"/proc/{self.proc.pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def stop(self, within=10):
        """SIGTERM; the seconds it took to exit (None: killed after `within`)."""
        if self.proc.poll() is not None:
            return 0.0
        start = time.monotonic()
        self.proc.send_signal(signal.SIGTERM)
        try:
            self.proc.wait(timeout=within)
            return time.monotonic() - start
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            return None

    def log(self):
        self.err.seek(0)
        return self.err.read().decode(errors="replace")


def tcp_request(port, payload, timeout=5.0):
    """One request, its first reply's payload (None on timeout)."""
    with socket.create_connection(("127.0.0.1", port), timeout=timeout) as s:
        s.sendall(frame(payload))
        data = b""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            start = data.find(b"\x02USP")
            if start >= 0 and len(data) >= start + 8:
                size = struct.unpack(">I", data[start + 4:start + 8])[0]
                if len(data) >= start + 9 + size:
                    return data[start + 8:start + 8 + size]
            try:
                chunk = s.recv(65536)
            except socket.timeout:
                return None
            if not chunk:
                return None
            data += chunk
    return None


class Control:
    def __init__(self, path):
        deadline = time.monotonic() + 10
        while True:
            try:
                self.s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                self.s.settimeout(10)
                self.s.connect(path)
                break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.05)
        self.f = self.s.makefile("r")
        self.f.readline()  # greeting

    def command(self, execute, **arguments):
        self.s.sendall((json.dumps({"execute": execute, "arguments": arguments}) + "\n").encode())
        while True:
            reply = json.loads(self.f.readline())
            if "return" in reply or "error" in reply:
                return reply


def fail(message, daemon=None):
    if daemon is not None:
        daemon.stop()
        message += "\n--- stderr ---\n" + daemon.log()[-3000:]
    sys.exit(message)


def case_delay_reply(emud, scene, _):
    with tempfile.TemporaryDirectory() as tmp:
        d = Daemon(emud, scene, control=os.path.join(tmp, "c"))
        c = Control(os.path.join(tmp, "c"))
        reply = c.command("inject-fault", kind="delay_reply", delay_s=60, duration_s=1e6, transport="tcp")
        if "return" not in reply:
            fail(f"delay_s 60 refused: {reply}", d)
        before = d.hwm_kib()
        host = socket.create_connection(("127.0.0.1", d.port), timeout=10)
        burst = frame(bytes.fromhex("0102")) * 1000
        for _ in range(60):  # 60 000 pipelined GET_STATUS, none read
            host.sendall(burst)
        status = None
        for _ in range(100):  # the daemon reads them at its pace: wait until it has all
            status = c.command("query-status")["return"]
            if status["counters"]["telegrams_received"] >= 60000:
                break
            time.sleep(0.1)
        growth_mib = (d.hwm_kib() - before) / 1024
        dropped = status["counters"].get("delayed_replies_dropped")
        print(f"60000 delayed GET_STATUS: VmHWM +{growth_mib:.1f} MiB, delayed_replies_dropped={dropped}")
        if growth_mib > 24:
            fail(f"VmHWM grew {growth_mib:.1f} MiB for 60000 delayed replies: the queue is not bounded", d)
        if dropped is None or dropped < 60000 - 64:
            fail(f"delayed_replies_dropped={dropped}: expected all but 64 replies dropped", d)
        too_long = c.command("inject-fault", kind="delay_reply", delay_s=1e6, transport="tcp")
        if "error" not in too_long or "at most 60" not in too_long["error"]["desc"]:
            fail(f"delay_s 1e6 accepted: {too_long}", d)
        host.close()
        c.command("clear-fault")
        if tcp_request(d.port, bytes.fromhex("0102")) is None:
            fail("no GET_STATUS reply after the fault was cleared", d)
        if "dropping this one" not in d.log():
            fail("no warning about dropped delayed replies", d)
        d.stop()


def case_garbage(emud, scene, _):
    with tempfile.TemporaryDirectory() as tmp:
        d = Daemon(emud, scene, control=os.path.join(tmp, "c"))
        c = Control(os.path.join(tmp, "c"))
        for arguments, word in [({"kind": "garbage", "bytes": 4294967295, "transport": "tcp"}, "bytes"),
                                ({"kind": "garbage", "bytes": 4097}, "bytes"),
                                ({"kind": "bandwidth", "bytes_per_s": 125000001}, "bytes_per_s"),
                                ({"kind": "drop_reply", "count": 1e13}, "count"),
                                ({"kind": "tcp_stall", "duration_s": 2e6}, "duration_s")]:
            reply = c.command("inject-fault", **arguments)
            if "error" not in reply or word not in reply["error"]["desc"]:
                fail(f"{arguments} accepted or unclear: {reply}", d)
        before = d.hwm_kib()
        if "return" not in c.command("inject-fault", kind="garbage", bytes=4096, transport="tcp"):
            fail("garbage bytes=4096 (the maximum) refused", d)
        with socket.create_connection(("127.0.0.1", d.port), timeout=5) as s:
            s.sendall(frame(bytes.fromhex("0102")))
            data = b""
            while len(data) < 4096 + 15:
                chunk = s.recv(65536)
                if not chunk:
                    break
                data += chunk
        growth_mib = (d.hwm_kib() - before) / 1024
        print(f"garbage 4096: {len(data)} bytes received, VmHWM +{growth_mib:.1f} MiB")
        if len(data) != 4096 + 15 or data[-15:-11] != b"\x02USP":
            fail(f"expected 4096 garbage bytes and the reply, got {len(data)} bytes", d)
        d.stop()


def case_control_fd_exhaustion(emud, scene, _):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "c")
        d = Daemon(emud, scene, control=path,
                   preexec=lambda: resource.setrlimit(resource.RLIMIT_NOFILE, (64, 64)))
        clients = []
        for _ in range(80):
            s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            s.setblocking(False)
            try:
                s.connect(path)
            except (BlockingIOError, OSError):
                pass
            clients.append(s)
        cpu_before = d.cpu_s()
        time.sleep(2.0)
        cpu = d.cpu_s() - cpu_before
        for s in clients:  # the daemon's descriptors come back: the hosts are served again
            s.close()
        answered = False
        for _ in range(10):
            answered = tcp_request(d.port, bytes.fromhex("0102"), timeout=1.0) is not None
            if answered:
                break
        stop_s = d.stop()
        log = d.log()
        warnings = sum(1 for line in log.splitlines() if "control: accept" in line)
        print(f"80 control clients at RLIMIT_NOFILE 64: CPU {cpu:.2f} s in 2 s, {warnings} warnings, "
              f"GET_STATUS answered: {answered}, exit after SIGTERM {stop_s} s")
        if cpu > 1.0:
            fail(f"the daemon used {cpu:.2f} s of CPU in 2 s: its control accept loop spins\n" + log)
        if warnings == 0 or warnings > 3:
            fail(f"{warnings} 'control: accept' warnings (expected 1..3: said once, then every 10 s)\n" + log)
        if not answered or stop_s is None:
            fail("the daemon did not answer GET_STATUS or SIGTERM\n" + log)


def pcapng_whole(path):
    """True when the file is a sequence of whole pcapng blocks; the number of blocks."""
    with open(path, "rb") as f:
        data = f.read()
    offset, blocks = 0, 0
    while offset < len(data):
        if len(data) - offset < 12:
            return False, blocks
        length = struct.unpack("<I", data[offset + 4:offset + 8])[0]
        if length < 12 or length % 4 or offset + length > len(data):
            return False, blocks
        offset += length
        blocks += 1
    return True, blocks


def case_record_files(emud, scene, _):
    with tempfile.TemporaryDirectory() as tmp:
        record = os.path.join(tmp, "r.pcapng")
        run = subprocess.run([emud, "--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash",
                              "--timeout", "3", "--record", record, "--record-max-mb", "1",
                              "--record-files", "10000000"], capture_output=True, text=True, timeout=60)
        print(f"--record-files 10000000: exit {run.returncode} {run.stderr.strip()}")
        if run.returncode != 2 or "--record-files" not in run.stderr:
            sys.exit("--record-files 10000000 was not a usage error (exit 2)")
        # Rotation at 64 KiB keeping 1000 files: the loop keeps answering, the files keep their order.
        d = Daemon(emud, scene, extra=["--record", record, "--record-max-mb", "0.0625", "--record-files", "1000"])
        with socket.create_connection(("127.0.0.1", d.port), timeout=10) as s:
            for _ in range(30):  # 30 x 2000 GET_STATUS, each reply read: about 1.5 MB of capture
                s.sendall(frame(bytes.fromhex("0102")) * 2000)
                data = b""
                while data.count(b"\x02USP") < 2000:
                    chunk = s.recv(1 << 16)
                    if not chunk:
                        fail("connection closed while rotating", d)
                    data += chunk
        stop_s = d.stop()
        files = sorted(n for n in os.listdir(tmp) if n.startswith("r.pcapng"))
        print(f"rotation at 64 KiB: {len(files)} files, exit after SIGTERM {stop_s} s")
        if stop_s is None:
            fail("SIGTERM not honoured within 10 s while rotating")
        if any(".rotating" in name for name in files) or len(files) < 10:
            fail(f"files after rotation: {files[:12]}")
        for name in files:
            whole, _ = pcapng_whole(os.path.join(tmp, name))
            if not whole:
                fail(f"{name} does not end at a block boundary")


def ignore_sigxfsz_and_limit(size):
    def preexec():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # the write then fails with EFBIG: a "full disk"
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))
    return preexec


def case_record_full_disk(emud, scene, replay):
    with tempfile.TemporaryDirectory() as tmp:
        record = os.path.join(tmp, "r.pcapng")
        d = Daemon(emud, scene, extra=["--record", record], preexec=ignore_sigxfsz_and_limit(30001))
        with socket.create_connection(("127.0.0.1", d.port), timeout=10) as s:
            for _ in range(400):
                s.sendall(frame(bytes.fromhex("0102")))
                data = b""
                while len(data) < 15:
                    chunk = s.recv(64)
                    if not chunk:
                        fail("connection closed", d)
                    data += chunk
        answered = tcp_request(d.port, bytes.fromhex("0102")) is not None
        d.stop()
        log = d.log()
        whole, blocks = pcapng_whole(record)
        errors = sum(1 for line in log.splitlines() if "--record:" in line)
        print(f"recording at RLIMIT_FSIZE 30001: {os.path.getsize(record)} bytes, {blocks} whole blocks, "
              f"ends at a block boundary: {whole}, {errors} error line(s), answered after: {answered}")
        if not whole:
            fail("the recording cut off by the full disk ends inside a block\n" + log)
        if errors != 1:
            fail(f"{errors} '--record:' error lines (expected exactly 1)\n" + log)
        if not answered:
            fail("the daemon stopped answering after the write error\n" + log)
        if replay:
            for name, cut in [("whole", None), ("cut", 7)]:
                path = record
                if cut:  # a file that ends inside its last block, as another writer may leave it
                    path = os.path.join(tmp, "cut.pcapng")
                    with open(record, "rb") as f:
                        data = f.read()
                    with open(path, "wb") as f:
                        f.write(data[:-cut])
                run = subprocess.run([replay, path, "--tcp", "tcp:127.0.0.1:0", "--timeout", "0.3"],
                                     capture_output=True, text=True, timeout=60)
                print(f"ldoem-replay of the {name} file: exit {run.returncode}; "
                      + " | ".join(run.stderr.strip().splitlines()[:2]))
                if run.returncode != 0:
                    sys.exit(f"ldoem-replay refused the {name} recording:\n{run.stderr}")
                if cut and "cut short" not in run.stderr:
                    sys.exit("ldoem-replay did not warn about the cut file:\n" + run.stderr)


def case_event_log_full(emud, scene, _):
    with tempfile.TemporaryDirectory() as tmp:
        # /dev/full is no regular file: refused at start with a clear word (issue 27 item 3).
        d = Daemon(emud, scene, extra=["--event-log", "/dev/full"], expect_start=False)
        d.stop()
        refused = d.proc.returncode == 2 and "is a character device" in d.log()
        print(f"--event-log /dev/full: exit {d.proc.returncode}: {d.log().strip().splitlines()[-1:]}")
        if not refused:
            fail("--event-log /dev/full was not refused at start as a character device\n" + d.log())
        # A full disk (RLIMIT_FSIZE 1500, SIGXFSZ ignored: EFBIG): whole records, reported once,
        # every lost record counted, the daemon goes on.
        events = os.path.join(tmp, "events.jsonl")
        d = Daemon(emud, scene, control=os.path.join(tmp, "c2"), extra=["--event-log", events],
                   preexec=ignore_sigxfsz_and_limit(1500))
        c = Control(os.path.join(tmp, "c2"))
        for _ in range(40):
            c.command("inject-fault", kind="window_dirt", fraction=0.5, duration_s=1)
        d.stop()
        with open(events, "rb") as f:
            data = f.read()
        lines = data.split(b"\n")
        whole = data.endswith(b"\n") and all(json.loads(line) for line in lines[:-1])
        print(f"--event-log on a full disk: {len(data)} bytes, {len(lines) - 1} records, whole: {whole}")
        if not whole:
            fail(f"the event log ends mid-record: ...{data[-60:]!r}\n" + d.log())
        if sum(1 for line in d.log().splitlines() if "--event-log" in line) != 1:
            fail("the full disk was not reported exactly once\n" + d.log())


def case_identification(emud, scene, _):
    with tempfile.TemporaryDirectory() as tmp:
        with open(scene) as f:
            body = f.read()
        for length, should_start in [(6000, False), (5814, True)]:
            path = os.path.join(tmp, f"id{length}.yaml")
            with open(path, "w") as f:
                f.write(f"scanner:\n  identification:\n    sensor_name: \"{'N' * length}\"\n" + body)
            d = Daemon(emud, path, expect_start=should_start)
            if not should_start:
                if d.port is not None:
                    fail(f"a {length}-character sensor_name was accepted: the daemon started", d)
                d.proc.wait(timeout=30)
                first = d.log().strip().splitlines()[:1]
                print(f"sensor_name of {length} characters: exit {d.proc.returncode} {first}")
                if d.proc.returncode != 2 or "at most 5814" not in d.log():
                    fail(f"a {length}-character sensor_name was not refused at load", d)
                continue
            reply = tcp_request(d.port, bytes.fromhex("01010001"))
            d.stop()
            print(f"sensor_name of {length} characters: reply payload {len(reply) if reply else None} bytes")
            if reply is None or len(reply) != 5816:
                fail(f"GET_IDENTIFICATION 1 with a {length}-character name: {len(reply) if reply else 'no'} reply")


def case_listen_backlog(emud, scene, _):
    d = Daemon(emud, scene)
    os.kill(d.proc.pid, signal.SIGSTOP)  # it accepts nothing: only the kernel's backlog holds them
    try:
        clients = []
        for _ in range(200):
            s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            s.setblocking(False)
            s.connect_ex(("127.0.0.1", d.port))
            clients.append(s)
        time.sleep(0.5)  # a SYN dropped for a full backlog is retried after 1 s
        _, writable, _ = select.select([], clients, [], 0)
        done = sum(1 for s in writable if s.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR) == 0)
    finally:
        os.kill(d.proc.pid, signal.SIGCONT)
    for s in clients:
        s.close()
    d.stop()
    print(f"200 connects to a stopped daemon: {done} completed within 0.5 s")
    if done < 200:
        sys.exit(f"only {done} of 200 connections completed: the listen backlog is too small")


if __name__ == "__main__":
    case, emud, scene = sys.argv[1:4]
    replay = sys.argv[4] if len(sys.argv) > 4 else None
    globals()["case_" + case](emud, scene, replay)
