"""Profile telegrams in an ldoem-emud recording (--record FILE, docs/capture.md): when the device
sent each one, in device time. The fault matrix counts the profiles sent after a fault from it,
exactly (the event log has fault times, the recording profile times, both on the device clock).

TCP only: the recording's TCP interface has one synthesized IPv4/TCP segment per telegram piece;
a telegram's first segment starts with its TCP frame (02 'USP' LENGTH PAYLOAD), and a profile's
payload with 83 01. Serial and CAN recordings are not read here (None)."""

import struct

LINKTYPE_IPV4 = 228
TCP_FRAME_HEAD = b"\x02USP"
DEVICE_PORT = 49152


def _blocks(data, endian):
    offset = 0
    while offset + 12 <= len(data):
        block_type, length = struct.unpack_from(endian + "II", data, offset)
        if length < 12 or offset + length > len(data):
            return  # a block cut short: the writer was stopped mid-write
        yield block_type, data[offset + 8:offset + length - 4]
        offset += length


def profile_times(path):
    """Device times (s) of the profile telegrams sent to TCP hosts, in file order."""
    return [time for time, payload in device_telegrams(path) if payload[:2] == b"\x83\x01"]


def refusals(path):
    """The SERVICE_FAILURE replies (D2: FF 00 REQUEST REASON) sent to TCP hosts: (device time s,
    request code, reason), in file order: requests the device refused in the state it was in."""
    out = []
    for time, payload in device_telegrams(path):
        if payload[:2] == b"\xff\x00" and len(payload) >= 6:
            request, reason = struct.unpack_from(">HH", payload, 2)
            out.append((time, request, reason))
    return out


def device_telegrams(path):
    """(device time s, payload) of each telegram the device sent to a TCP host (its first
    segment: the payload may be cut at the segment's end, enough for its code)."""
    with open(path, "rb") as file:
        data = file.read()
    if len(data) < 12 or struct.unpack_from("<I", data, 0)[0] != 0x0A0D0D0A:
        raise ValueError(f"{path}: not a pcapng file")
    endian = "<" if struct.unpack_from("<I", data, 8)[0] == 0x1A2B3C4D else ">"
    link_types = []
    times = []
    for block_type, body in _blocks(data, endian):
        if block_type == 1:  # interface description
            link_types.append(struct.unpack_from(endian + "H", body, 0)[0])
        elif block_type == 6:  # enhanced packet
            interface, high, low, captured = struct.unpack_from(endian + "IIII", body, 0)
            if interface >= len(link_types) or link_types[interface] != LINKTYPE_IPV4:
                continue
            packet = body[20:20 + captured]
            header = (packet[0] & 0x0F) * 4
            source_port = struct.unpack_from(">H", packet, header)[0]
            tcp_header = (packet[header + 12] >> 4) * 4
            payload = packet[header + tcp_header:]
            if source_port == DEVICE_PORT and payload[:4] == TCP_FRAME_HEAD:
                times.append((((high << 32) | low) / 1e9, payload[8:]))  # if_tsresol 9: nanoseconds
    return times
