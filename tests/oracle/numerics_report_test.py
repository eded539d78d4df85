#!/usr/bin/env python3
"""scripts/numerics-report's fault summary and --faults-file, against a stand-in numerics_sweep.

The stand-in prints the tallies a sweep prints (key=value lines) and writes 6,000 fault lines to
its --faults-file; two jobs make 12,000, of which the report keeps the cap of 10,000 in seed order
and counts the rest. No caster runs: the report's own arithmetic is what is checked.
  numerics_report_test.py SOURCE_DIR
"""
import pathlib
import subprocess
import sys
import tempfile

FAKE_SWEEP = r'''#!/usr/bin/env python3
import sys
args = dict(zip(sys.argv[1::2], sys.argv[2::2]))
seed = int(args["--seed"])
with open(args["--faults-file"], "a") as out:
    for i in range(6000):
        out.write(f"{'moving' if i % 3 else 'embree'} range {seed:02x}{i:04x} skipped part {i}\n")
print(f"seed={seed}\ncases=10\nrays=100\nrange_faults=6000\nfault_cases=2")
print("faults_by.embree.range=2000\nfaults_by.moving.range=4000")
for i in range(6):
    print(f"fault=moving range: skipped part {i}; case {seed:02x}{i:04x}")
print("faults_file_written=6000\nfaults_file_dropped=0")
'''


def main():
    source = pathlib.Path(sys.argv[1])
    with tempfile.TemporaryDirectory() as scratch:
        build = pathlib.Path(scratch) / "build"
        sweep = build / "tests/oracle/numerics_sweep"
        sweep.parent.mkdir(parents=True)
        sweep.write_text(FAKE_SWEEP)
        sweep.chmod(0o755)
        faults = pathlib.Path(scratch) / "faults.txt"
        result = subprocess.run([sys.executable, str(source / "scripts/numerics-report"), "--build", str(build),
                                 "--jobs", "2", "--seconds", "1", "--seed", "7", "--faults-file", str(faults)],
                                capture_output=True, text=True)
        report = result.stdout
        failures = []

        def check(condition, what):
            if not condition:
                failures.append(what)

        check(result.returncode == 1, f"exit status {result.returncode} (1: faults), stderr {result.stderr[-500:]}")
        check("By caster and kind: embree range 4000, moving range 8000; in 4 distinct cases." in report,
              "the per-caster-and-kind summary")
        check("Faults (the first 10 of 12000; every sweep fault's case is in the --faults-file file, 10,000 lines "
              "(2,000 more past its cap of 10,000 not kept)):" in report, "the faults heading")
        check(report.count("\n- moving range: skipped part") == 10, "ten faults listed")
        lines = faults.read_text().splitlines() if faults.exists() else []
        check(len(lines) == 10000, f"{len(lines)} lines in the faults file (10000)")
        check(lines[:1] == ["embree range 070000 skipped part 0"], f"first line {lines[:1]} (seed 7's first)")
        check(lines[6000:6001] == ["embree range 080000 skipped part 0"], "seed 8's lines follow seed 7's")
        for f in failures:
            print("FAIL:", f)
        if failures:
            print(report)
        return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
