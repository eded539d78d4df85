#!/usr/bin/env python3
"""Copies a pcapng capture with the device's TCP port 49152 changed to another one, TCP checksums
recomputed: a capture of an LD-OEM configured to another port, for the tests of ldoem-replay
--port, ldoem-conformance --against and the dissector's port preference (docs/wireshark.md).

Usage: rewrite_port.py IN.pcapng OUT.pcapng PORT
Only the raw IPv4 interfaces (LINKTYPE_IPV4, 228) of ldoem's own captures are rewritten."""
import struct
import sys

LINKTYPE_IPV4 = 228
OLD_PORT = 49152


def checksum(data):
    if len(data) % 2:
        data += b"\0"
    total = sum(struct.unpack(f"!{len(data) // 2}H", data))
    while total >> 16:
        total = (total & 0xFFFF) + (total >> 16)
    return ~total & 0xFFFF


def rewrite_ipv4(packet, port):
    if len(packet) < 20 or packet[0] >> 4 != 4 or packet[9] != 6:
        return packet
    header = (packet[0] & 0x0F) * 4
    total = struct.unpack("!H", packet[2:4])[0]
    tcp = bytearray(packet[header:total])
    source, destination = struct.unpack("!HH", tcp[0:4])
    source = port if source == OLD_PORT else source
    destination = port if destination == OLD_PORT else destination
    tcp[0:4] = struct.pack("!HH", source, destination)
    tcp[16:18] = b"\0\0"
    pseudo = packet[12:20] + struct.pack("!BBH", 0, 6, len(tcp))
    tcp[16:18] = struct.pack("!H", checksum(pseudo + bytes(tcp)))
    return packet[:header] + bytes(tcp) + packet[total:]


def main():
    source, target, port = sys.argv[1], sys.argv[2], int(sys.argv[3])
    data = bytearray(open(source, "rb").read())
    order = "<"
    link_types = []
    offset = 0
    while offset + 12 <= len(data):
        if struct.unpack("<I", data[offset:offset + 4])[0] == 0x0A0D0D0A:
            order = "<" if data[offset + 8:offset + 12] == b"\x4d\x3c\x2b\x1a" else ">"
            link_types = []
        block_type, length = struct.unpack(order + "II", data[offset:offset + 8])
        if block_type == 1:
            link_types.append(struct.unpack(order + "H", data[offset + 8:offset + 10])[0])
        elif block_type == 6:
            interface, _, _, captured = struct.unpack(order + "IIII", data[offset + 8:offset + 24])
            if link_types[interface] == LINKTYPE_IPV4:
                start = offset + 28
                packet = bytes(data[start:start + captured])
                rewritten = rewrite_ipv4(packet, port)
                assert len(rewritten) == len(packet)
                data[start:start + captured] = rewritten
        offset += length
    open(target, "wb").write(bytes(data))


if __name__ == "__main__":
    main()
