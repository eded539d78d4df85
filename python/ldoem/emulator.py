"""ldoem-emud from Python: start it on a scene (a path or a dict), on free ports or given
endpoints, optionally in virtual time; talk to its control socket; always stop it."""

import json
import os
import selectors
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

from . import capture
from .control import ControlClient

try:
    from . import _paths
except ImportError:  # a package copied without its generated paths
    _paths = None


def find_program(name, env):
    """$env, then this build's or installation's program, then PATH."""
    if os.environ.get(env):
        return os.environ[env]
    built = getattr(_paths, "EMUD" if name == "ldoem-emud" else "SCAN", None) if _paths else None
    if built and os.path.exists(built):
        return built
    found = shutil.which(name)
    if not found:
        raise FileNotFoundError(f"{name} not found: set {env} or put it on PATH")
    return found


def scene_path(name):
    """A scene shipped with ldoem by its name ("corridor" or "faults/flaky-tcp"), as a path."""
    root = os.environ.get("LDOEM_SCENES") or (getattr(_paths, "SCENES", None) if _paths else None) or "scenes"
    path = Path(root) / (name if name.endswith(".yaml") else name + ".yaml")
    if not path.exists():
        raise FileNotFoundError(f"no scene {path}")
    return path


class EmulatorError(RuntimeError):
    """ldoem-emud did not start (its stderr is in the message) or did not stop."""


class Emulator:
    """One ldoem-emud process.

    scene         a path, a scene name (scene_path) or a dict (written as a temporary YAML file;
                  JSON is YAML)
    transports    any of "tcp", "serial" (a pty), "lpt" (the tilt stepper on a pty), "can"
    tcp           "HOST:PORT" to listen on; default 127.0.0.1 on a free port
    serial, lpt   the path the pty is linked at; default a temporary folder's
    can           the SocketCAN interface for "can" [vcan0] (it must exist and be up)
    virtual_time  --virtual-time (D7): the clock jumps when the daemon is idle
    args          more ldoem-emud options
    record        --record: every telegram with its device time (docs/capture.md); read with
                  profile_times() before stop()
    After start(): .device (the first host endpoint, as libldoem writes it), .tcp, .serial, .can, .lpt,
    .control (a ControlClient), .event_log_path.
    """

    def __init__(self, scene="minimal", transports=("tcp",), tcp=None, virtual_time=False, seed=None, args=(),
                 start_timeout=30.0, stop_timeout=10.0, emud=None, record=False, serial=None, lpt=None,
                 can="vcan0"):
        self.scene = scene
        self.transports = tuple(transports)
        self.tcp_listen = tcp
        self.serial_link = serial
        self.lpt_link = lpt
        self.can_interface = can
        self.virtual_time = virtual_time
        self.seed = seed
        self.args = list(args)
        self.record = record
        self.start_timeout = start_timeout
        self.stop_timeout = stop_timeout
        self.emud = emud or find_program("ldoem-emud", "LDOEM_EMUD")
        self.process = None
        self.returncode = None
        self.tcp = self.serial = self.lpt = self.can = self.device = None
        self._control = None
        self._workdir = None
        self._final_events = None
        self._final_profile_times = None
        self._final_refusals = None

    # ------------------------------------------------------------------ life cycle
    def start(self):
        self._workdir = tempfile.mkdtemp(prefix="ldoem-emu-")
        work = Path(self._workdir)
        if isinstance(self.scene, dict):
            scene = work / "scene.yaml"
            scene.write_text(json.dumps(self.scene))
        elif isinstance(self.scene, (str, os.PathLike)) and os.path.exists(self.scene):
            scene = Path(self.scene)
        else:
            scene = scene_path(str(self.scene))
        self.control_path = work / "control.sock"
        self.event_log_path = work / "events.log"
        command = [self.emud, "--scene", str(scene), "--no-flash", "--control", str(self.control_path),
                   "--event-log", str(self.event_log_path)]
        command += ["--can", f"can:{self.can_interface}"] if "can" in self.transports else ["--no-can"]
        if "tcp" in self.transports:
            command += ["--tcp", f"tcp:{self.tcp_listen or '127.0.0.1:0'}"]
        if "serial" in self.transports:
            command += ["--serial", f"serial:pty:{self.serial_link or work / 'serial'}"]
        if "lpt" in self.transports:
            command += ["--lpt", f"lpt:pty:{self.lpt_link or work / 'lpt'}"]
        if self.virtual_time:
            command.append("--virtual-time")
        if self.seed is not None:
            command += ["--seed", str(self.seed)]
        self.record_path = work / "capture.pcapng"
        if self.record:
            command += ["--record", str(self.record_path)]
        command += self.args
        self._stderr = open(work / "emud.err", "w+b")
        self.process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=self._stderr,
                                        start_new_session=True)
        try:
            self._read_endpoints()
        except BaseException:
            self.stop()
            raise
        return self

    def _read_endpoints(self):
        deadline = time.monotonic() + self.start_timeout
        lines = []
        buffer = b""
        with selectors.DefaultSelector() as selector:
            selector.register(self.process.stdout, selectors.EVENT_READ)
            while "ready" not in lines:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise EmulatorError(f"ldoem-emud not ready within {self.start_timeout} s: {self.stderr_text()}")
                if not selector.select(min(left, 0.1)):
                    if self.process.poll() is not None:
                        raise EmulatorError(f"ldoem-emud exited with {self.process.returncode}: {self.stderr_text()}")
                    continue
                chunk = os.read(self.process.stdout.fileno(), 4096)
                if not chunk:
                    self.process.wait(timeout=5)
                    raise EmulatorError(f"ldoem-emud exited with {self.process.returncode}: {self.stderr_text()}")
                buffer += chunk
                *complete, buffer = buffer.split(b"\n")
                lines += [line.decode() for line in complete]
        for line in lines:
            kind, _, value = line.partition(" ")
            if kind == "tcp":
                self.tcp = f"tcp:{value}"
            elif kind == "serial":  # "serial /dev/pts/N SYMLINK"
                self.serial = f"serial:{value.split()[0]}"
            elif kind == "lpt":
                self.lpt = f"lpt:pty:{value.split()[0]}"
            elif kind == "can":  # "can vcan0 6C0:6C1"
                self.can = "can:" + ":".join(value.split())
        self.device = self.tcp or self.serial or self.can

    def stderr_text(self):
        self._stderr.seek(0)
        return self._stderr.read().decode(errors="replace").strip()

    def stop(self):
        """quit through the control socket, then SIGTERM, then SIGKILL: the process never outlives
        this call. Returns its exit status."""
        if self.process is None:
            return self.returncode
        if self.process.poll() is None:
            try:
                with ControlClient(self.control_path, timeout=2.0) as client:
                    client.quit()
            except (OSError, RuntimeError, ValueError):
                pass
            for sig, wait in ((None, self.stop_timeout), (signal.SIGTERM, 5.0), (signal.SIGKILL, 5.0)):
                if sig is not None:
                    try:
                        self.process.send_signal(sig)
                    except ProcessLookupError:
                        pass
                try:
                    self.process.wait(timeout=wait)
                    break
                except subprocess.TimeoutExpired:
                    continue
        self.returncode = self.process.returncode
        # The daemon writes its event log through a buffer: the whole log is there once it ended.
        self._final_events = self._read_event_log()
        self._final_profile_times = self._read_profile_times()
        self._final_refusals = self._read_capture(capture.refusals)
        self.process.stdout.close()
        if self._control is not None:
            self._control.close()
            self._control = None
        self._stderr.close()
        shutil.rmtree(self._workdir, ignore_errors=True)
        self.process = None
        return self.returncode

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()

    @property
    def running(self):
        return self.process is not None and self.process.poll() is None

    # ------------------------------------------------------------------ control socket
    @property
    def control(self):
        if self._control is None:
            self._control = ControlClient(self.control_path)
        return self._control

    def inject_fault(self, kind, **fault):
        return self.control.inject_fault(kind, **fault)

    def clear_fault(self, id=None, scanner=None):  # noqa: A002
        return self.control.clear_fault(id=id, scanner=scanner)

    def query_faults(self, scanner=None):
        return self.control.query_faults(scanner=scanner)

    def query_status(self, scanner=None):
        return self.control.query_status(scanner=scanner)

    def power_cycle(self, off_s=None, scanner=None):
        return self.control.power_cycle(off_s=off_s, scanner=scanner)

    def move_object(self, name, position_m, rpy_deg=None, at_s=None, keep_velocity=None):
        return self.control.move_object(name, position_m, rpy_deg=rpy_deg, at_s=at_s, keep_velocity=keep_velocity)

    def add_object(self, object, at_s=None):  # noqa: A002
        return self.control.add_object(object, at_s=at_s)

    def remove_object(self, name, at_s=None):
        return self.control.remove_object(name, at_s=at_s)

    def events(self, timeout=None):
        """The daemon's events as they come (see ControlClient.events)."""
        return self.control.events(timeout=timeout)

    def event_log(self):
        """Every event from --event-log, as dicts: complete once the daemon has stopped (it
        buffers its writes), so far while it runs."""
        if self.process is None and self._final_events is not None:
            return self._final_events
        return self._read_event_log()

    def profile_times(self):
        """Device times (s) of the profiles sent over TCP, from the recording (record=True), or
        None without one. Complete once the daemon has stopped."""
        if self.process is None:
            return self._final_profile_times
        return self._read_profile_times()

    def refusals(self):
        """(device time s, request code, D2 reason) of each SERVICE_FAILURE sent over TCP, from
        the recording (record=True), or None without one. Complete once the daemon has stopped."""
        if self.process is None:
            return self._final_refusals
        return self._read_capture(capture.refusals)

    def _read_profile_times(self):
        return self._read_capture(capture.profile_times)

    def _read_capture(self, reader):
        if not self.record:
            return None
        try:
            return reader(self.record_path)
        except (FileNotFoundError, ValueError):
            return None

    def _read_event_log(self):
        try:
            text = Path(self.event_log_path).read_text()
        except FileNotFoundError:
            return []
        return [json.loads(line) for line in text.splitlines() if line.strip()]
