#!/usr/bin/env python3
"""Issue 27: ldoem-emud on paths that are not what they claim, and on scenes and meshes whose
size was only checked after the memory was spent. Each CASE fails before its fix:
  fifo      --scene, --flash, --event-log, --record naming a FIFO hung start-up in open() (SIGTERM
            ignored); now exit 2 at once with "is a FIFO" (D7, D11).
  flash     a 0-byte --flash was rewritten with the defaults (exit 0); a symlinked --flash became a
            regular file at exit; temporary files of a killed save stayed forever (D12, D13).
  memory    1 000 000 sphere lines (58 MB): 5.9 GB and 62 s before the object limit; --scene
            /dev/zero: 2.1 GB, then std::bad_alloc; a binary STL header claiming 5 000 000
            triangles: 1.66 GB in assimp. Now each is exit 2 with a located message under a
            768 MiB address-space limit (D6, D7, D8); the sphere lines stop at the YAML node
            limit (12 nodes a line). Label `plain`: RLIMIT_AS.
Every run of the daemon is bounded by a wall-time limit; a hang is a failure, not a stuck test.
usage: hostile_files_test.py EMUD SCENE CASE"""
import os, resource, struct, subprocess, sys, tempfile

emud, scene, case = sys.argv[1:4]
if case == "memory":  # as out_of_memory_test.py: no RLIMIT_AS lets a sanitizer's shadow memory start
    linked = subprocess.run(["ldd", emud], capture_output=True, text=True).stdout
    with open(emud, "rb") as program:
        if b"AddressSanitizer" in program.read() or "libasan" in linked or "libtsan" in linked:
            sys.exit("sanitizer build: RLIMIT_AS cannot be applied; run this case on a plain build")
LIMIT_S = 30
failures = []

def run(args, rlimit_mib=None, timeout=LIMIT_S):
    def limit():
        if rlimit_mib:
            resource.setrlimit(resource.RLIMIT_AS, (rlimit_mib << 20, rlimit_mib << 20))
    base = [emud, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--timeout", "0.3"]
    try:
        done = subprocess.run(base + args, capture_output=True, text=True, timeout=timeout, preexec_fn=limit)
        return done.returncode, done.stderr
    except subprocess.TimeoutExpired as expired:  # subprocess.run has killed it (SIGKILL)
        return None, f"no exit within {timeout} s: {expired.stderr!r}"

def expect(label, outcome, code, text):
    rc, err = outcome
    ok = rc == code and text in err
    print(f"{'ok  ' if ok else 'FAIL'} {label}: exit {rc}, {err.strip().splitlines()[-1] if err.strip() else ''}")
    if not ok:
        failures.append(f"{label}: want exit {code} and {text!r}, got exit {rc}:\n{err}")

with tempfile.TemporaryDirectory() as folder:
    fifo = os.path.join(folder, "fifo")
    os.mkfifo(fifo)
    flash = os.path.join(folder, "x.flash")
    if case == "fifo":
        expect("--scene FIFO", run(["--scene", fifo, "--no-flash"]), 2, "is a FIFO")
        expect("--flash FIFO", run(["--scene", scene, "--flash", fifo]), 2, "is a FIFO")
        expect("--event-log FIFO", run(["--scene", scene, "--no-flash", "--event-log", fifo]), 2, "is a FIFO")
        expect("--record FIFO", run(["--scene", scene, "--no-flash", "--record", fifo]), 2, "is a FIFO")
        expect("--scene folder", run(["--scene", folder, "--no-flash"]), 2, "is a directory")
    elif case == "flash":
        open(flash, "w").close()
        expect("--flash empty file", run(["--scene", scene, "--flash", flash]), 2, "empty")
        if os.path.getsize(flash) != 0:
            failures.append("the empty flash file was rewritten")
        os.remove(flash)
        real = os.path.join(folder, "real.flash")
        expect("--flash new file", run(["--scene", scene, "--flash", real]), 0, "")
        os.symlink("real.flash", flash)
        stale = os.path.join(folder, ".real.flash.Ab12Z9")
        open(stale, "w").close()
        expect("--flash symlink", run(["--scene", scene, "--flash", flash, "--log-level", "info"]), 0,
               "removed 1 temporary file")
        if not os.path.islink(flash):
            failures.append("the symlinked flash was replaced by a regular file")
        if os.path.exists(stale):
            failures.append("the temporary file of a killed save was not removed")
    elif case == "memory":
        many = os.path.join(folder, "many.yaml")
        with open(many, "w") as f:
            f.write("objects:\n")
            f.write("  - {sphere: {radius_m: 0.5}, pose: {position_m: [5, 0, 0]}}\n" * 1000000)
        expect("1e6 sphere lines", run(["--scene", many, "--no-flash"], rlimit_mib=768), 2,
               "more than 1000000 YAML nodes")
        expect("--scene /dev/zero", run(["--scene", "/dev/zero", "--no-flash"], rlimit_mib=768), 2,
               "is a character device")
        stl = os.path.join(folder, "huge.stl")
        with open(stl, "wb") as f:
            f.write(b"x" * 80 + struct.pack("<I", 5000000))
            f.truncate(84 + 50 * 5000000)  # sparse zeros
        stl_scene = os.path.join(folder, "stl.yaml")
        with open(stl_scene, "w") as f:
            f.write("objects: [{mesh: {file: huge.stl}}]\n")
        expect("STL claiming 5e6 triangles", run(["--scene", stl_scene, "--no-flash"], rlimit_mib=768), 2,
               "5000000 triangles")
    else:
        sys.exit(f"unknown case {case}")

if failures:
    sys.exit("\n".join(failures))
