#!/usr/bin/env python3
"""One ldoem-hub client session for scripts/check-fleet.sh (docs/hub.md, message protocol 1).

  hub_session.py HOST:PORT [--timeout S] STEP...

Each STEP is `send:LINE` (a request; its ID is the line's first word), `expect:ID:REGEX` (wait
for the reply with that ID and match it, `ID OK ...` or `ID ERR ...`), or `notice:REGEX` (wait
for an unsolicited `* ...` line matching it, or take one already received). Every line read is
printed with `<`, every request with `>`. Exit 0 when every step passed, 1 at the first that did
not (with the reason), 2 on a usage error. Each wait is bounded by --timeout (default 20 s).
"""
import re
import socket
import sys
import time


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(argv) > 1 else 2
    host, _, port = argv[1].rpartition(":")
    steps = argv[2:]
    timeout = 20.0
    if steps[:1] == ["--timeout"]:
        timeout = float(steps[1])
        steps = steps[2:]
    sock = socket.create_connection((host, int(port)), timeout=timeout)
    buffer = b""
    replies = {}
    notices = []

    def read_line(deadline):
        nonlocal buffer
        while b"\n" not in buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            sock.settimeout(left)
            try:
                chunk = sock.recv(65536)
            except socket.timeout:
                return None
            if not chunk:
                raise ConnectionError("the hub closed the connection")
            buffer += chunk
        line, buffer = buffer.split(b"\n", 1)
        text = line.decode("ascii", "replace").rstrip("\r")
        print("<", text if len(text) < 300 else text[:300] + "...", flush=True)
        return text

    def wait_for(predicate, what):
        deadline = time.monotonic() + timeout
        while True:
            found = predicate()
            if found:
                return found
            line = read_line(deadline)
            if line is None:
                raise TimeoutError(f"no {what} within {timeout:g} s")
            if line.startswith("* "):
                notices.append(line)
            else:
                replies[line.split(" ", 1)[0]] = line

    try:
        for step in steps:
            kind, _, rest = step.partition(":")
            if kind == "send":
                print(">", rest, flush=True)
                sock.sendall(rest.encode("ascii") + b"\n")
            elif kind == "expect":
                ident, _, pattern = rest.partition(":")
                line = wait_for(lambda: replies.pop(ident, None), f"reply {ident}")
                if not re.search(pattern, line):
                    print(f"hub_session: reply {ident} does not match `{pattern}`: {line[:200]}", file=sys.stderr)
                    return 1
            elif kind == "notice":
                def match():
                    for i, line in enumerate(notices):
                        if re.search(rest, line):
                            return notices.pop(i)
                    return None
                wait_for(match, f"notice matching `{rest}`")
            else:
                print(f"hub_session: unknown step `{step}`", file=sys.stderr)
                return 2
    except (OSError, TimeoutError, ConnectionError) as error:
        print(f"hub_session: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
