#!/usr/bin/env python3
"""Issue 11: Embree errors and std::bad_alloc escaping Daemon::create made ldoem-emud abort
(SIGABRT, exit 134, a core dump). Under address-space limits from 64 to 512 MiB the daemon must
start and stop (0), or stop with a message (1 or 2); only the dynamic loader may fail (127)
before our code runs. At least one limit must reach a failure inside the daemon, so that the
test tests something. (Before the fix: SIGABRT from 96 to 192 MiB with scenes/minimal.yaml,
"terminate called after throwing ... Embree: cannot create a device".)
usage: out_of_memory_test.py EMUD SCENE"""
import resource, subprocess, sys

emud, scene = sys.argv[1:3]
# The sanitizers reserve terabytes of shadow memory: no RLIMIT_AS lets them start. gcc links
# their runtime as a shared library, clang into the program. ctest runs this on the plain build
# only (label plain); run by hand on a sanitizer build, it says so and fails.
linked = subprocess.run(["ldd", emud], capture_output=True, text=True).stdout
with open(emud, "rb") as program:
    sanitized = b"AddressSanitizer" in program.read() or "libasan" in linked or "libtsan" in linked
if sanitized:
    sys.exit("sanitizer build: RLIMIT_AS cannot be applied; run this test on a plain build")

failures_inside = 0
for mib in range(64, 513, 32):
    def limit(m=mib):
        resource.setrlimit(resource.RLIMIT_AS, (m << 20, m << 20))
    run = subprocess.run([emud, "--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash",
                          "--timeout", "0.3"], preexec_fn=limit, capture_output=True, text=True, timeout=60)
    last = run.stderr.strip().splitlines()[-1] if run.stderr.strip() else ""
    print(f"RLIMIT_AS {mib} MiB: exit {run.returncode} {last}")
    if run.returncode < 0 or run.returncode >= 128:
        sys.exit(f"ldoem-emud died of a signal ({run.returncode}) at {mib} MiB:\n{run.stderr}")
    if run.returncode in (1, 2):
        if not last.startswith("ldoem-emud: "):
            sys.exit(f"exit {run.returncode} at {mib} MiB without a message:\n{run.stderr}")
        failures_inside += 1
    elif run.returncode not in (0, 127):
        sys.exit(f"unexpected exit {run.returncode} at {mib} MiB:\n{run.stderr}")
if failures_inside == 0:
    sys.exit("no limit made the daemon fail: the test did not reach the out-of-memory path")
