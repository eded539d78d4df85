"""A deliberately naive LD-OEM client for ldoem.torture's tests and docs/python.md: it connects,
configures the motor, starts measuring and reads 20 profiles, with no retry, no reconnect and no
reset. Any fault that costs a reply or the connection ends it with exit 1.

    python3 naive_client.py ENDPOINT     (or LDOEM_DEVICE)
"""

import os
import sys

import ldoem


def main():
    endpoint = sys.argv[1] if len(sys.argv) > 1 else os.environ["LDOEM_DEVICE"]
    with ldoem.Scanner(endpoint, request_timeout=2.0) as scanner:
        scanner.configure(motor_speed_hz=10)
        scanner.rotate()
        scanner.measure()
        with scanner.profiles(count=20, timeout=2.0) as stream:
            points = sum(len(profile) for profile in stream)
    print(f"naive_client: 20 profiles, {points} points")


if __name__ == "__main__":
    try:
        main()
    except ldoem.Error as error:
        print(f"naive_client: {error}", file=sys.stderr)
        sys.exit(1)
