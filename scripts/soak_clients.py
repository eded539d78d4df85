"""The soak test's clients (scripts/soak.sh): host-protocol streams straight to ldoem-emud over
TCP, and ldoem-hub line-protocol clients. Every reply is checked; a wrong one is recorded in a
Failures list rather than raised, so one bad reply does not hide the next."""

import functools
import random
import socket
import threading
import time

PROFILE_FORMAT = 0x3DFF  # range + echo (spec 3.5), what S1 asks for
MEASURE = 3  # low nibble of the status byte in MEASURE mode (spec 2.4)
IO_TIMEOUT_S = 10.0


class Failures:
    """Thread-safe list of what went wrong; keeps the first few messages and a count."""

    def __init__(self, keep=20):
        self.lock = threading.Lock()
        self.messages = []
        self.count = 0
        self.keep = keep

    def add(self, message):
        with self.lock:
            self.count += 1
            if len(self.messages) < self.keep:
                self.messages.append(message)


class Tally:
    """Counters every client adds to (replies checked, connections, steps moved)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.values = {}

    def add(self, key, amount=1):
        with self.lock:
            self.values[key] = self.values.get(key, 0) + amount


def frame(payload):
    """A TCP telegram (spec 4.1): STX 'USP', length, payload, XOR of the payload."""
    checksum = functools.reduce(lambda a, b: a ^ b, payload, 0)
    return b"\x02USP" + len(payload).to_bytes(4, "big") + payload + bytes([checksum])


class TelegramReader:
    """Reads whole TCP telegrams from a socket and checks their framing and checksum."""

    def __init__(self, sock):
        self.sock = sock
        self.buffer = bytearray()

    def next(self):
        while True:
            if len(self.buffer) >= 8:
                if self.buffer[:4] != b"\x02USP":
                    raise ValueError(f"bad telegram start {self.buffer[:8].hex()}")
                length = int.from_bytes(self.buffer[4:8], "big")
                if length > 65536:
                    raise ValueError(f"telegram length {length}")
                if len(self.buffer) >= 9 + length:
                    payload = bytes(self.buffer[8:8 + length])
                    checksum = self.buffer[8 + length]
                    del self.buffer[:9 + length]
                    if functools.reduce(lambda a, b: a ^ b, payload, 0) != checksum:
                        raise ValueError("telegram checksum mismatch")
                    return payload
            data = self.sock.recv(65536)
            if not data:
                raise EOFError("connection closed by the daemon")
            self.buffer += data


def word(data, offset):
    return int.from_bytes(data[offset:offset + 2], "big")


def parse_profile(payload):
    """Checks a 0x8301 telegram of format 0x3DFF field by field (spec 3.5) and returns
    (profile_sent, measurement) where measurement is what a static scene repeats exactly:
    per sector its number, step, start and end angle and the (distance, echo) pairs."""
    if word(payload, 0) != 0x8301 or word(payload, 2) != PROFILE_FORMAT:
        raise ValueError(f"not a 0x3DFF profile: {payload[:4].hex()}")
    sectors = word(payload, 4)
    profile_sent = word(payload, 6)
    if word(payload, 10) != 0:
        raise ValueError("LAYERNUM is not 0")
    offset, measurement = 12, []
    for _ in range(sectors):
        if offset + 10 > len(payload):
            raise ValueError("profile ends inside a sector header")
        number, step, points, start = word(payload, offset), word(payload, offset + 2), word(payload, offset + 4), word(payload, offset + 8)
        offset += 10
        samples = payload[offset:offset + 4 * points]
        offset += 4 * points
        end = word(payload, offset + 2)
        offset += 4
        if points and (start + (points - 1) * step) % 5760 != end % 5760:
            raise ValueError(f"sector {number}: {points} points from {start} by {step} do not end at {end}")
        measurement.append((number, step, start, end, bytes(samples)))
    if offset + 4 != len(payload):
        raise ValueError(f"profile is {len(payload)} bytes, its fields say {offset + 4}")
    if payload[offset + 3] & 0x0F != MEASURE or payload[offset + 3] >> 4 != 0:
        raise ValueError(f"SENSTAT status byte {payload[offset + 3]:#04x}, not MEASURE with the motor ok")
    return profile_sent, tuple(measurement)


def put_in_measure(port):
    """TRANS_ROTATE then TRANS_MEASURE on a fresh connection; returns one reference profile."""
    with socket.create_connection(("127.0.0.1", port), timeout=IO_TIMEOUT_S) as sock:
        reader = TelegramReader(sock)
        for request, reply in (("04030000", 0x8403), ("0404", 0x8404)):
            sock.sendall(frame(bytes.fromhex(request)))
            answer = reader.next()
            if word(answer, 0) != reply:
                raise ValueError(f"{request}: reply {answer.hex()}")
        sock.sendall(frame(bytes.fromhex("03010001") + PROFILE_FORMAT.to_bytes(2, "big")))
        return parse_profile(reader.next())[1]


def tcp_streamer(port, reference, deadline, seed, failures, tally):
    """Connects, streams a few profiles (GET_PROFILE 0), sometimes asks GET_STATUS in between,
    then drops the connection one of four ways: close, CANCEL_PROFILE then close, reset (RST),
    or close in the middle of a telegram. Every profile must equal the static scene's reference
    and count up by one; the device must stay in MEASURE."""
    rng = random.Random(seed)
    while time.monotonic() < deadline:
        try:
            sock = socket.create_connection(("127.0.0.1", port), timeout=IO_TIMEOUT_S)
        except OSError as error:
            failures.add(f"tcp connect: {error}")
            time.sleep(0.5)
            continue
        tally.add("tcp_connections")
        reader = TelegramReader(sock)
        drop = rng.choice(("close", "cancel", "reset", "mid_telegram"))
        try:
            sock.sendall(frame(bytes.fromhex("03010000") + PROFILE_FORMAT.to_bytes(2, "big")))
            expected_sent = 1
            status_asked = False
            for _ in range(rng.randint(2, 15)):
                if not status_asked and rng.random() < 0.3:
                    sock.sendall(frame(bytes.fromhex("0102")))
                    status_asked = True
                payload = reader.next()
                if word(payload, 0) == 0x8102:
                    if len(payload) < 6 or payload[5] & 0x0F != MEASURE:
                        failures.add(f"GET_STATUS reply {payload.hex()}")
                    status_asked = False
                    tally.add("tcp_replies")
                    continue
                sent, measurement = parse_profile(payload)
                if sent != expected_sent:
                    failures.add(f"PROFILESENT {sent}, expected {expected_sent}")
                if measurement != reference:
                    failures.add(f"profile {sent} differs from the static scene's reference")
                expected_sent = sent + 1
                tally.add("tcp_profiles")
            if drop == "cancel":
                sock.sendall(frame(bytes.fromhex("0302")))
                while True:  # profiles already on their way may come before the reply
                    payload = reader.next()
                    if word(payload, 0) == 0x8302:
                        tally.add("tcp_replies")
                        break
                    if word(payload, 0) not in (0x8301, 0x8102):
                        failures.add(f"unexpected telegram after CANCEL_PROFILE: {payload[:8].hex()}")
                        break
            elif drop == "reset":
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
            elif drop == "mid_telegram":
                sock.recv(rng.randint(1, 100))
        except (OSError, ValueError, EOFError) as error:
            failures.add(f"tcp stream ({drop}): {error}")
        finally:
            sock.close()
        time.sleep(rng.uniform(0.0, 0.3))


class HubConnection:
    """One line-protocol client of ldoem-hub (docs/hub.md)."""

    def __init__(self, port):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=IO_TIMEOUT_S)
        self.buffer = b""
        greeting = self.line()
        if not greeting.startswith("* OK HELLO "):
            raise ValueError(f"greeting {greeting!r}")

    def line(self):
        while b"\n" not in self.buffer:
            data = self.sock.recv(65536)
            if not data:
                raise EOFError("hub closed the connection")
            self.buffer += data
        text, self.buffer = self.buffer.split(b"\n", 1)
        return text.decode()

    def request(self, request_id, device, command):
        """Sends one request; returns the KEY=VALUE fields of its OK reply (raises otherwise)."""
        self.sock.sendall(f"{request_id} {device} {command}\n".encode())
        reply = self.line()
        words = reply.split(" ")
        name = command.split(" ")[0]
        if words[:3] != [request_id, "OK", name]:
            raise ValueError(f"{request_id} {device} {command}: reply {reply[:200]!r}")
        return dict(field.split("=", 1) for field in words[3:])

    def close(self):
        self.sock.close()


def hub_client(port, devices, lpt_device, deadline, seed, failures, tally):
    """One of the hub's clients: STATUS, GET2DPROFILE and, on the device with a tilt stepper,
    MOVEMOTOR up then the same steps down, round after round; reconnects now and then. The
    moves balance, so the tilt ends where it started (soak.py checks that and the LPT steps)."""
    rng = random.Random(seed)
    number = 0
    while time.monotonic() < deadline:
        try:
            hub = HubConnection(port)
        except (OSError, ValueError, EOFError) as error:
            failures.add(f"hub connect: {error}")
            time.sleep(0.5)
            continue
        tally.add("hub_connections")
        moved_up = 0
        try:
            for _ in range(rng.randint(5, 40)):
                if time.monotonic() >= deadline:
                    break
                device = rng.choice(devices)
                number += 1
                status = hub.request(f"c{seed}.{number}", device, "STATUS")
                if status.get("mode") != "measure" or status.get("motor") != "ok":
                    failures.add(f"hub STATUS on {device}: {status}")
                number += 1
                profile = hub.request(f"c{seed}.{number}", device, "GET2DPROFILE")
                parse_profile(bytes.fromhex(profile["profile"]))
                int(profile["tilt_half_steps"])
                tally.add("hub_replies", 2)
                if device == lpt_device:
                    steps = rng.randint(1, 4)
                    for direction in ("up", "down"):
                        number += 1
                        hub.request(f"c{seed}.{number}", device, f"MOVEMOTOR {steps} {direction} half")
                        moved_up += steps if direction == "up" else -steps
                        tally.add("half_steps", steps)
                        tally.add("hub_replies")
        except (OSError, ValueError, EOFError, KeyError) as error:
            failures.add(f"hub client {seed}: {error}")
            if moved_up:  # an up without its down: the final tilt check would fail; say why
                failures.add(f"hub client {seed} left the tilt {moved_up} half steps up")
        finally:
            hub.close()
