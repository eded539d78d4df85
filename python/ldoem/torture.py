"""python3 -m ldoem.torture [options] -- CMD ARGS...

Runs CMD once per fault scenario (ldoem.faults) against a fresh ldoem-emud, for drivers in any
language. `{device}` in CMD's arguments becomes the emulator's endpoint (tcp:HOST:PORT or
serial:PATH) and `{lpt}` the tilt stepper's (lpt:pty:PATH; the emulator then has one); both are
also in the environment as LDOEM_DEVICE and LDOEM_LPT. Each run is judged by CMD's exit status,
the time limit and the emulator's event log; the recording adds the profiles sent after the fault
and the requests the device refused (SERVICE_FAILURE replies, D2), reported beside the verdict:

  recovered     exit 0 after the fault acted, and profiles flowed after it    pass
  completed     exit 0 after the fault acted, no profile after it       pass
  unaffected    exit 0, the fault never acted (the trigger's request was not sent)  pass
  gave up       exit != 0 after a final device fault (motor_stall, motor_overspeed,
                encoder_error: libldoem's reset_device)                 pass
  failed        exit != 0 after any other fault, or without one; or
                ldoem-emud itself died during the run                   FAIL
  hung          still running at the time limit (then killed)            FAIL
  crashed       ended by a signal                                        FAIL

Writes OUT/matrix.md, OUT/junit.xml and OUT/matrix.png (scenario x outcome). Exit status 0 when
every scenario passed, 1 when one failed, 2 on a usage error.
"""

import argparse
import concurrent.futures
import dataclasses
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from . import faults
from .emulator import Emulator

PASSING = {"recovered": True, "completed": True, "unaffected": True, "gave up": True, "failed": False, "hung": False, "crashed": False}
COLOURS = {"recovered": "#4caf50", "completed": "#a5d6a7", "unaffected": "#b0bec5", "gave up": "#ffca28", "failed": "#e53935",
           "hung": "#8e24aa", "crashed": "#000000"}


@dataclasses.dataclass
class Run:
    scenario: faults.Scenario
    verdict: str
    exit_status: object
    seconds: float
    device: str
    profiles_after_fault: object
    output: str
    refusals: int = 0

    @property
    def passed(self):
        return PASSING[self.verdict]


def judge(scenario, exit_status, hung, triggered, profiles_after_fault=None):
    if hung:
        return "hung"
    if exit_status < 0:
        return "crashed"
    if exit_status == 0:
        if not triggered:
            return "unaffected"
        return "recovered" if profiles_after_fault else "completed"
    if triggered and scenario.kind in faults.FINAL_KINDS:
        return "gave up"
    return "failed"


def run_one(scenario, command, options):
    transports = (scenario.transport,) + (("lpt",) if any("{lpt}" in arg for arg in command) else ())
    with Emulator(options.scene, transports=transports, virtual_time=not options.real_time, record=True) as emulator:
        emulator.inject_fault(scenario.kind, **scenario.fault())
        lpt = emulator.lpt or ""
        argv = [arg.replace("{device}", emulator.device).replace("{lpt}", lpt) for arg in command]
        env = dict(os.environ, LDOEM_DEVICE=emulator.device, LDOEM_LPT=lpt)
        started = time.monotonic()
        process = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                   env=env, start_new_session=True)
        hung = False
        try:
            output, _ = process.communicate(timeout=options.time_limit)
        except subprocess.TimeoutExpired:
            hung = True
            os.killpg(process.pid, signal.SIGKILL)
            output, _ = process.communicate()
        seconds = time.monotonic() - started
        outcome = faults.outcome_of(scenario, emulator)  # stops the emulator
    text = output.decode(errors="replace")[-4000:]
    verdict = judge(scenario, process.returncode, hung, outcome.triggered, outcome.profiles_after_fault)
    if outcome.daemon_exit is not None:
        verdict = "failed"  # the emulator itself died: nothing about the driver can be judged
    return Run(scenario, verdict, process.returncode, seconds, outcome.device if outcome.triggered else "not triggered",
               outcome.profiles_after_fault, text + "\n--- events\n" + "\n".join(map(str, outcome.events)),
               len(outcome.refusals))


def write_markdown(path, runs, title):
    triggers = list(dict.fromkeys(run.scenario.trigger for run in runs))
    kinds = list(dict.fromkeys(run.scenario.kind for run in runs))
    cell = {(run.scenario.kind, run.scenario.trigger): run for run in runs}
    lines = [f"### {title}", "", "| kind | " + " | ".join(triggers) + " |", "|---|" + "---|" * len(triggers)]
    for kind in kinds:
        row = []
        for trigger in triggers:
            run = cell.get((kind, trigger))
            row.append("" if run is None else f"{run.verdict}{'' if run.passed else ' **FAIL**'}")
        lines.append(f"| `{kind}` | " + " | ".join(row) + " |")
    passed = sum(run.passed for run in runs)
    lines += ["", f"{passed} of {len(runs)} scenarios passed."]
    Path(path).write_text("\n".join(lines) + "\n")


def write_junit(path, runs, title):
    failures = sum(not run.passed for run in runs)
    total = sum(run.seconds for run in runs)
    parts = [f'<?xml version="1.0" encoding="utf-8"?>\n<testsuites><testsuite name={quoteattr(title)} '
             f'tests="{len(runs)}" failures="{failures}" errors="0" time="{total:.3f}">']
    for run in runs:
        scenario = run.scenario
        parts.append(f'<testcase classname={quoteattr("torture." + scenario.transport)} name={quoteattr(scenario.id)} '
                     f'time="{run.seconds:.3f}"><properties>'
                     f'<property name="verdict" value={quoteattr(run.verdict)}/>'
                     f'<property name="device" value={quoteattr(run.device)}/>'
                     f'<property name="profiles_after_fault" value={quoteattr(str(run.profiles_after_fault))}/>'
                     f'<property name="refused_requests" value="{run.refusals}"/>'
                     f'</properties>')
        if not run.passed:
            parts.append(f'<failure message={quoteattr(f"{run.verdict} (exit {run.exit_status})")}/>')
        parts.append(f"<system-out>{escape(run.output)}</system-out></testcase>")
    parts.append("</testsuite></testsuites>\n")
    Path(path).write_text("".join(parts))


def write_png(path, runs, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    triggers = list(dict.fromkeys(run.scenario.trigger for run in runs))
    kinds = list(dict.fromkeys(run.scenario.kind for run in runs))
    cell = {(run.scenario.kind, run.scenario.trigger): run for run in runs}
    figure, axes = plt.subplots(figsize=(3.0 + 2.2 * len(triggers), 1.2 + 0.42 * len(kinds)))
    for row, kind in enumerate(kinds):
        for column, trigger in enumerate(triggers):
            run = cell.get((kind, trigger))
            if run is None:
                continue
            axes.add_patch(plt.Rectangle((column, row), 1, 1, facecolor=COLOURS[run.verdict], edgecolor="white"))
            axes.text(column + 0.5, row + 0.5, run.verdict, ha="center", va="center", fontsize=9,
                      color="white" if run.verdict in ("failed", "hung", "crashed", "recovered") else "black")
    axes.set_xlim(0, len(triggers))
    axes.set_ylim(len(kinds), 0)
    axes.set_xticks([c + 0.5 for c in range(len(triggers))], triggers)
    axes.set_yticks([r + 0.5 for r in range(len(kinds))], kinds)
    axes.xaxis.tick_top()
    axes.tick_params(length=0)
    passed = sum(run.passed for run in runs)
    axes.set_title(f"{title}\n{passed} of {len(runs)} scenarios passed", pad=28)
    used = [verdict for verdict in COLOURS if any(run.verdict == verdict for run in runs)]
    axes.legend(handles=[Patch(facecolor=COLOURS[v], label=f"{v} ({'pass' if PASSING[v] else 'FAIL'})") for v in used],
                loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, title="outcome")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--" not in argv:
        if "--help" in argv or "-h" in argv:
            print(__doc__)
            return 0
        print("ldoem.torture: usage: python3 -m ldoem.torture [options] -- CMD ARGS... (try --help)", file=sys.stderr)
        return 2
    split = argv.index("--")
    parser = argparse.ArgumentParser(prog="python3 -m ldoem.torture", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--transport", default="tcp", choices=("tcp", "serial", "can"))
    parser.add_argument("--scene", default="minimal", help="scene path or name [minimal]")
    parser.add_argument("--kinds", help="comma-separated D11 kinds [every one of the transport]")
    parser.add_argument("--triggers", help="comma-separated trigger points [all: " + ",".join(faults.TRIGGERS) + "]")
    parser.add_argument("--time-limit", type=float, default=60.0, help="seconds per run [60]")
    parser.add_argument("--jobs", type=int, default=1, help="runs at once [1]")
    parser.add_argument("--real-time", action="store_true", help="the emulator in real time [virtual time]")
    parser.add_argument("--out", default="torture-out", help="folder for matrix.md, junit.xml, matrix.png")
    parser.add_argument("--title", help="the matrix's title [the command]")
    options = parser.parse_args(argv[:split])
    command = argv[split + 1:]
    if not command:
        parser.error("no command after --")
    try:
        chosen = faults.scenarios(options.transport, options.kinds.split(",") if options.kinds else None,
                                  options.triggers.split(",") if options.triggers else None)
    except ValueError as error:
        parser.error(str(error))
    title = options.title or " ".join(Path(command[0]).name if i == 0 else a for i, a in enumerate(command))
    out = Path(options.out)
    out.mkdir(parents=True, exist_ok=True)
    runs = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, options.jobs)) as pool:
        futures = [pool.submit(run_one, scenario, command, options) for scenario in chosen]
        for future in futures:
            run = future.result()
            runs.append(run)
            print(f"{'pass' if run.passed else 'FAIL'} {run.scenario.id}: {run.verdict} (exit {run.exit_status}, "
                  f"{run.seconds:.1f} s; {run.device})", flush=True)
    write_markdown(out / "matrix.md", runs, title)
    write_junit(out / "junit.xml", runs, title)
    write_png(out / "matrix.png", runs, title)
    failed = sum(not run.passed for run in runs)
    print(f"ldoem.torture: {len(runs) - failed} of {len(runs)} scenarios passed; {out}/matrix.md, junit.xml, matrix.png")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
