#!/usr/bin/env python3
"""Runs tshark with tools/wireshark/*.lua on captures and compares the decoded fields.

Two sources of captures:
  * the fixtures program (--fixtures): spec section 7 vectors and generated profiles on TCP,
    CAN (ISO-TP) and serial; the expected values are the spec's own (written below) and the
    profiles the fixtures program encoded (profiles.json);
  * captures recorded from the emulator (--capture FILE --expect FILE.json, repeatable): the
    expectation lists each transport's telegrams (service code, and point counts for profiles).
Every telegram must decode, no packet may be malformed or hit a Lua error, and expert infos
must appear exactly where a capture was damaged on purpose. Exit 0 when all agree.
"""
import argparse
import json
import os
import subprocess
import sys

import yaml

SERVICES = {
    "GET_IDENTIFICATION": 0x0101, "GET_STATUS": 0x0102, "GET_SIGNAL": 0x0104, "SET_SIGNAL": 0x0105,
    "SET_CONFIG": 0x0201, "GET_CONFIG": 0x0202, "SET_TIME_ABS": 0x0203, "SET_TIME_REL": 0x0204,
    "GET_SYNC_CLOCK": 0x0205, "SET_FILTER": 0x0209, "SET_FUNCTION": 0x020A, "GET_FUNCTION": 0x020B,
    "GET_PROFILE": 0x0301, "CANCEL_PROFILE": 0x0302, "DO_RESET": 0x0401, "TRANS_IDLE": 0x0402,
    "TRANS_ROTATE": 0x0403, "TRANS_MEASURE": 0x0404, "Profile": 0x8301,
}

# Field values the spec's section 7 states in words, keyed by the vector's name. Lists are every
# occurrence in order (tshark's repeated fields).
SPEC_FIELDS = {
    "SET_CONFIG global id 1, 10 Hz, 0.5°": {"ldoem.config.key": "0x0010", "ldoem.config.sensor_id": "1",
                                           "ldoem.config.motor_speed": "10", "ldoem.config.angle_step": "8"},
    "GET_CONFIG Ethernet": {"ldoem.config.key": "0x0005"},
    "SET_TIME_ABS 1000 ms": {"ldoem.time": "1000"},
    "SET_TIME_REL −10 ms": {"ldoem.time_delta": "-10"},
    "SET_FILTER near-field on": {"ldoem.filter.item": "1", "ldoem.filter.value": "1"},
    "SET_FUNCTION s1 no-meas 314.5° temp": {"ldoem.sector.number": "1", "ldoem.sector.function": "1",
                                            "ldoem.sector.stop": "5032", "ldoem.sector.stop_deg": "314.5",
                                            "ldoem.sector.flash": "0"},
    "GET_FUNCTION s7": {"ldoem.sector.number": "7"},
    "GET_PROFILE stream 0x3DFF": {"ldoem.request.profiles": "0", "ldoem.profile.format": "0x3dff"},
    "GET_PROFILE 1 × 0x39FF": {"ldoem.request.profiles": "1", "ldoem.profile.format": "0x39ff"},
    "DO_RESET level 2": {"ldoem.reset.level": "0x0002"},
    "TRANS_ROTATE 10 Hz (layout per S1, non-zero value per S2's semantics)": {"ldoem.rotate.speed": "10"},
    "SET_SIGNAL 0x11 (yellow A + switch 0)": {"ldoem.port": "0x0011", "ldoem.port.led_a": "1", "ldoem.port.led_b": "0",
                                              "ldoem.port.outputs": "0x0001"},
    "GET_STATUS, IDLE, motor OK": {"ldoem.status.sensor_mode": "1", "ldoem.status.motor_mode": "0x00"},
    "GET_STATUS, MEASURE, motor OK": {"ldoem.status.sensor_mode": "3"},
    "TRANS_ROTATE → ROTATE, motor OK": {"ldoem.status.sensor_mode": "2"},
    "TRANS_MEASURE refused, code 2": {"ldoem.status.sensor_mode": "2", "ldoem.measure.return_code": "2"},
    "GET_CONFIG global (1, 10 Hz, 8 ticks)": {"ldoem.config.sensor_id": "1", "ldoem.config.motor_speed": "10",
                                              "ldoem.config.angle_step": "8"},
    "GET_CONFIG Ethernet 192.168.1.10/255.255.255.0/192.168.1.1, node 0, port 0": {
        "ldoem.config.ip": "192.168.1.10", "ldoem.config.mask": "255.255.255.0", "ldoem.config.gateway": "192.168.1.1",
        "ldoem.config.node_id": "0", "ldoem.config.tcp_port": "0"},
    "SET_CONFIG success": {"ldoem.result": "0x0000"},
    "GET_FUNCTION s0 normal 270°": {"ldoem.sector.number": "0", "ldoem.sector.function": "3",
                                    "ldoem.sector.stop_deg": "270"},
    "SET_FUNCTION invalid": {"ldoem.result": "0xffff"},
    "GET_SIGNAL port 0x01": {"ldoem.port.led_a": "1"},
    "GET_SYNC_CLOCK 0x1234 ms": {"ldoem.time": "4660"},
    "DO_RESET level 2": {"ldoem.reset.level": "0x0002"},
    "GET_IDENTIFICATION, text 'LD-OEM' (text illustrative)": {"ldoem.ident.text": "LD-OEM"},
    "Profile 0x39FF: sent 1, count 100, layer 0, sector 0, step 0.5°, 3 points, t 0x1234→0x1236 ms, 0°→1°, distances 1 m / 2.5 m / 0": {
        "ldoem.profile.sent": "1", "ldoem.profile.count": "100", "ldoem.profile.layer": "0", "ldoem.profile.step": "8",
        "ldoem.profile.points": "3", "ldoem.profile.tstart": "4660", "ldoem.profile.tend": "4662",
        "ldoem.profile.enddir": "16", "ldoem.profile.distance_m": ["1", "2.5", "0"], "ldoem.status.sensor_mode": "3",
        "ldoem.profile.total_points": "3"},
    "Profile 0x3DFF: same header, 2 points at 180°/180.5°, (1 m, echo 200), (2.5 m, echo 80)": {
        "ldoem.profile.points": "2", "ldoem.profile.startdir": "2880", "ldoem.profile.enddir": "2888",
        "ldoem.profile.echo": ["200", "80"], "ldoem.profile.distance_m": ["1", "2.5"]},
}
# Serial vectors whose bytes break a rule on purpose: expert info expected there.
SERIAL_EXPERTS = {"GET_CONFIG key 1 (S2's LEN 6)": "ldoem_serial.bad_length"}


def walk(node, out, prefix):
    """Collects every field under `node` whose name starts with `prefix`, through subtrees."""
    if isinstance(node, dict):
        for key, value in node.items():
            if isinstance(value, str):
                if key.startswith(prefix):
                    out.setdefault(key, []).append(value)
            elif isinstance(value, list) and all(isinstance(v, str) for v in value):
                if key.startswith(prefix):
                    out.setdefault(key, []).extend(value)
            elif key != "ldoem" or prefix != "ldoem.":
                walk(value, out, prefix)
    elif isinstance(node, list):
        for item in node:
            walk(item, out, prefix)


def find_telegrams(node, found):
    """Every 'ldoem' protocol node (one per telegram), anywhere in a packet's layers."""
    if isinstance(node, dict):
        for key, value in node.items():
            if key == "ldoem":
                for item in value if isinstance(value, list) else [value]:
                    fields = {}
                    walk(item, fields, "ldoem.")
                    found.append(fields)
            else:
                find_telegrams(value, found)
    elif isinstance(node, list):
        for item in node:
            find_telegrams(item, found)


def run_tshark(args, capture, extra=()):
    command = [args.tshark, "-n", "-r", capture, "-T", "json", "--no-duplicate-keys",
               "-X", "lua_script:" + os.path.join(args.lua_dir, "ldoem.lua"),
               "-X", "lua_script:" + os.path.join(args.lua_dir, "ldoem_serial.lua"),
               "-o", "iso15765.can.ids:1728-1729", "-d", "iso15765.subdissector,ldoem_isotp", *extra]
    result = subprocess.run(command, capture_output=True, text=True, timeout=240)
    if result.returncode != 0:
        sys.exit(f"tshark failed ({result.returncode}): {result.stderr}")
    packets = json.loads(result.stdout)
    per_transport = {"tcp": [], "can": [], "serial": []}
    problems = []
    for packet in packets:
        layers = packet["_source"]["layers"]
        number = layers["frame"]["frame.number"]
        text = json.dumps(layers)
        if "_ws.malformed" in text or "_ws.lua" in text.replace("_ws.lua.fake", ""):
            problems.append(f"frame {number}: malformed or Lua error: {text[:400]}")
        transport = "tcp" if "tcp" in layers else "can" if "can" in layers else "serial" if "ldoem_serial" in layers else None
        telegrams = []
        find_telegrams(layers, telegrams)
        if transport is None and telegrams:
            problems.append(f"frame {number}: ldoem outside a known transport")
        for fields in telegrams:
            fields["_frame"] = number
            serial_fields = {}
            walk(layers.get("ldoem_serial", {}), serial_fields, "ldoem_serial.")
            fields["_serial"] = serial_fields
            per_transport[transport].append(fields)
    return per_transport, problems


def expect_equal(problems, where, field, want, got):
    if want != got:
        problems.append(f"{where}: {field}: expected {want!r}, tshark decoded {got!r}")


def check_service(problems, where, fields, code):
    expect_equal(problems, where, "ldoem.service", [f"0x{code:04x}"], fields.get("ldoem.service"))


def check_vectors(args, problems):
    vectors = yaml.safe_load(open(args.vectors, encoding="utf-8"))
    decoded, found = run_tshark(args, os.path.join(args.workdir, "vectors.pcapng"))
    problems += found
    rows = [(row["name"], False) for row in vectors["tcp_requests"]] + [(row["name"], True) for row in vectors["tcp_replies"]]
    serial_rows = [(row["name"], False) for row in vectors["serial_requests"]] + [(row["name"], True) for row in vectors["tcp_replies"]]
    for transport, expected in (("tcp", rows), ("can", rows), ("serial", serial_rows)):
        got = decoded[transport]
        if len(got) != len(expected):
            problems.append(f"vectors/{transport}: {len(expected)} telegrams written, {len(got)} decoded")
            continue
        for (name, reply), fields in zip(expected, got):
            where = f"vectors/{transport} frame {fields['_frame']} '{name}'"
            base = name.split(" ")[0].rstrip(",")
            code = SERVICES[base] | (0x8000 if reply else 0)
            check_service(problems, where, fields, code)
            for field, want in SPEC_FIELDS.get(name, {}).items():
                want_list = want if isinstance(want, list) else [want]
                expect_equal(problems, where, field, want_list, fields.get(field))
            experts = [k for k in fields if k.startswith("ldoem.expert.")] + \
                      [k for k in fields["_serial"] if k in ("ldoem_serial.bad_crc", "ldoem_serial.bad_length", "ldoem_serial.bad_hex")]
            want_experts = [SERIAL_EXPERTS[name]] if transport == "serial" and name in SERIAL_EXPERTS else []
            expect_equal(problems, where, "expert info", want_experts, sorted(set(experts) - {"ldoem.expert.bad_status"}))
    return sum(len(v) for v in decoded.values())


def check_other_port(args, problems, port=4000):
    """The vectors' capture moved to another TCP port (rewrite_port.py): not decoded as ldoem by
    default, decoded in full with the port preference or with Decode As (docs/wireshark.md)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import rewrite_port
    original = os.path.join(args.workdir, "vectors.pcapng")
    moved = os.path.join(args.workdir, f"vectors-port{port}.pcapng")
    subprocess.run([sys.executable, rewrite_port.__file__, original, moved, str(port)], check=True, timeout=60)
    want = len(run_tshark(args, original)[0]["tcp"])
    cases = (("no option", [], 0), ("the preference", ["-o", f"ldoem.tcp_port:{port}"], want),
             ("Decode As", ["-d", f"tcp.port=={port},ldoem"], want))
    for label, extra, expected in cases:
        decoded, found = run_tshark(args, moved, extra)
        problems += found
        got = len(decoded["tcp"])
        if got != expected or want == 0:
            problems.append(f"port {port} with {label}: {expected} TCP telegrams expected, tshark decoded {got}")


def check_profiles(problems, decoded, expected, label):
    for transport, profiles in expected.items():
        got = [t for t in decoded[transport] if t.get("ldoem.service") == ["0x8301"]]
        if len(got) != len(profiles):
            problems.append(f"{label}/{transport}: {len(profiles)} profiles expected, {len(got)} decoded")
            continue
        for index, (want, fields) in enumerate(zip(profiles, got)):
            where = f"{label}/{transport} profile {index} (frame {fields['_frame']})"
            expect_equal(problems, where, "ldoem.profile.total_points", [str(want["total"])], fields.get("ldoem.profile.total_points"))
            if want.get("format", 0) & 0x0020:
                expect_equal(problems, where, "ldoem.profile.points", [str(p) for p in want["points"]], fields.get("ldoem.profile.points"))
            if "first_distance_m" in want and want["total"] > 0 and want.get("format", 0) & 0x0100:
                first = float(fields.get("ldoem.profile.distance_m", ["nan"])[0])
                if abs(first - want["first_distance_m"]) > 1e-9:
                    problems.append(f"{where}: first distance {first} m, expected {want['first_distance_m']} m")


def check_generated_profiles(args, problems):
    decoded, found = run_tshark(args, os.path.join(args.workdir, "profiles.pcapng"))
    problems += found
    expected = json.load(open(os.path.join(args.workdir, "profiles.json")))
    check_profiles(problems, decoded, expected, "profiles")
    # The two damaged telegrams at the end, and nothing else, carry checksum expert infos.
    bad_checksums = [t["_frame"] for t in decoded["tcp"] if "ldoem.expert.bad_checksum" in t]
    bad_crcs = [t["_frame"] for t in decoded["serial"] if "ldoem_serial.bad_crc" in t["_serial"]]
    expect_equal(problems, "profiles", "frames with a bad checksum", 1, len(bad_checksums))
    expect_equal(problems, "profiles", "frames with a bad CRC", 1, len(bad_crcs))
    return sum(len(v) for v in decoded.values())


def check_recorded(args, problems, capture, expectation):
    decoded, found = run_tshark(args, capture)
    problems += found
    expected = json.load(open(expectation))
    for transport, telegrams in expected.get("telegrams", {}).items():
        got = decoded[transport]
        codes = [t.get("ldoem.service", ["?"])[0] for t in got]
        want = [f"0x{code:04x}" for code in telegrams]
        if codes != want:
            problems.append(f"{capture}/{transport}: {len(want)} telegrams recorded, tshark decoded {len(codes)}; "
                            f"first difference at {next((i for i, (a, b) in enumerate(zip(codes, want)) if a != b), min(len(codes), len(want)))}")
        for t in got:
            experts = [k for k in t if k.startswith("ldoem.expert.") and k not in ("ldoem.expert.bad_status", "ldoem.expert.service_failure")]
            if experts:
                problems.append(f"{capture}/{transport} frame {t['_frame']}: unexpected {experts}")
    check_profiles(problems, decoded, expected.get("profiles", {}), capture)
    return sum(len(v) for v in decoded.values())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tshark", default="tshark")
    parser.add_argument("--lua-dir", required=True)
    parser.add_argument("--fixtures", help="ldoem_dissector_fixtures binary (writes the vector and profile captures)")
    parser.add_argument("--vectors", help="tests/vectors/spec-section7.yaml")
    parser.add_argument("--workdir", default=".")
    parser.add_argument("--capture", action="append", default=[], help="a recorded capture (with --expect)")
    parser.add_argument("--expect", action="append", default=[], help="its expectation JSON")
    args = parser.parse_args()
    problems = []
    counted = 0
    if args.fixtures:
        os.makedirs(args.workdir, exist_ok=True)
        subprocess.run([args.fixtures, args.vectors, args.workdir], check=True, timeout=120)
        counted += check_vectors(args, problems)
        counted += check_generated_profiles(args, problems)
        check_other_port(args, problems)
    for capture, expectation in zip(args.capture, args.expect):
        counted += check_recorded(args, problems, capture, expectation)
    for problem in problems:
        print("FAIL", problem)
    print(f"check_dissector: {counted} telegrams decoded by tshark, {len(problems)} problems")
    return 1 if problems or counted == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
