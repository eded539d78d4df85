"""A client of ldoem-emud's control socket (--control PATH): JSON lines shaped like QEMU's QMP
(docs/faults.md "The control socket"). One method per command of the daemon's command table;
python/tests/test_control.py checks them against the daemon's `query-commands`, so the two
cannot drift apart."""

import collections
import json
import select
import socket
import time

# Events kept while a caller waits for a reply; older ones are dropped (counted in
# dropped_events), so a client that never reads events stays bounded.
MAX_QUEUED_EVENTS = 10000
MAX_LINE_BYTES = 1 << 20


class ControlError(Exception):
    """The daemon answered a command with an error object: error_class and desc."""

    def __init__(self, command, error_class, desc):
        super().__init__(f"{command}: {error_class}: {desc}")
        self.command = command
        self.error_class = error_class
        self.desc = desc


def _args(**arguments):
    return {key: value for key, value in arguments.items() if value is not None}


class ControlClient:
    """Connects to the socket and reads the greeting. Not thread-safe: one thread per client."""

    def __init__(self, path, timeout=10.0):
        self.path = str(path)
        self.timeout = timeout
        self._socket = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self._socket.settimeout(timeout)
        self._socket.connect(self.path)
        self._buffer = b""
        self._next_id = 1
        self._events = collections.deque(maxlen=MAX_QUEUED_EVENTS)
        self.dropped_events = 0
        greeting = self._read_message(time.monotonic() + timeout)
        if greeting is None or "QMP" not in greeting:
            raise ControlError("greeting", "GenericError", f"not an ldoem-emud control socket: {greeting!r}")
        self.greeting = greeting["QMP"]

    def close(self):
        self._socket.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ------------------------------------------------------------------ the wire
    def _read_message(self, deadline):
        """The next JSON line, or None at EOF; TimeoutError at the deadline."""
        while b"\n" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"{self.path}: no line from ldoem-emud within the timeout")
            readable, _, _ = select.select([self._socket], [], [], min(left, 0.05))
            if not readable:
                continue
            chunk = self._socket.recv(65536)
            if not chunk:
                return None
            self._buffer += chunk
            if len(self._buffer) > MAX_LINE_BYTES and b"\n" not in self._buffer:
                raise ControlError("read", "GenericError", "a line longer than 1 MiB")
        line, self._buffer = self._buffer.split(b"\n", 1)
        return json.loads(line)

    def _queue_event(self, message):
        if len(self._events) == self._events.maxlen:
            self.dropped_events += 1
        self._events.append(message)

    def execute(self, command, arguments=None, timeout=None):
        """Sends one command and returns its "return" value; ControlError for an error reply."""
        request_id = self._next_id
        self._next_id += 1
        request = {"execute": command, "id": request_id}
        if arguments:
            request["arguments"] = arguments
        self._socket.sendall(json.dumps(request).encode() + b"\n")
        deadline = time.monotonic() + (timeout if timeout is not None else self.timeout)
        while True:
            message = self._read_message(deadline)
            if message is None:
                if command == "quit":
                    return {}
                raise ControlError(command, "GenericError", "the daemon closed the control socket")
            if "event" in message:
                self._queue_event(message)
                continue
            if message.get("id") != request_id:
                continue
            if "error" in message:
                raise ControlError(command, message["error"].get("class", ""), message["error"].get("desc", ""))
            return message.get("return")

    def events(self, timeout=None):
        """Iterates over event messages ({"event", "data", "timestamp"}) as they come. Ends after
        `timeout` seconds without one (None: waits until the daemon closes the socket)."""
        while True:
            if self._events:
                yield self._events.popleft()
                continue
            deadline = time.monotonic() + (timeout if timeout is not None else 1e9)
            try:
                message = self._read_message(deadline)
            except TimeoutError:
                return
            if message is None:
                return
            if "event" in message:
                yield message

    # ------------------------------------------------------------------ the commands
    # Each method is one command: its name with "-" as "_", its arguments as keywords.
    def qmp_capabilities(self):
        return self.execute("qmp_capabilities")

    def query_commands(self):
        """The daemon's command table: [{"name": ..., "help": ..., "arguments": [...], "schema": {...}}, ...]."""
        return self.execute("query-commands")

    def inject_fault(self, kind, scanner=None, **fault):
        """A fault entry (docs/faults.md): kind plus its fields, e.g. duration_s=2, on={"service":
        "GET_STATUS", "nth": 3}. Returns the fault's id (0 while it waits for a trigger)."""
        return self.execute("inject-fault", _args(kind=kind, scanner=scanner, **fault))["id"]

    def clear_fault(self, id=None, scanner=None):  # noqa: A002 - the command's argument name
        return self.execute("clear-fault", _args(id=id, scanner=scanner))

    def query_faults(self, scanner=None):
        return self.execute("query-faults", _args(scanner=scanner))

    def query_status(self, scanner=None):
        return self.execute("query-status", _args(scanner=scanner))

    def power_cycle(self, off_s=None, scanner=None):
        return self.execute("power-cycle", _args(off_s=off_s, scanner=scanner))["id"]

    def move_object(self, name, position_m, rpy_deg=None, at_s=None, keep_velocity=None):
        return self.execute("move-object", _args(name=name, position_m=list(position_m),
                                                 rpy_deg=list(rpy_deg) if rpy_deg is not None else None,
                                                 at_s=at_s, keep_velocity=keep_velocity))

    def add_object(self, object, at_s=None):  # noqa: A002 - the command's argument name
        return self.execute("add-object", _args(object=object, at_s=at_s))

    def remove_object(self, name, at_s=None):
        return self.execute("remove-object", _args(name=name, at_s=at_s))

    def quit(self):
        return self.execute("quit")


def method_name(command):
    """The ControlClient method of a control-socket command."""
    return command.replace("-", "_")
