"""Writes the soak test's report (scripts/soak.sh --report FILE): a gnuplot PNG of every
process's RSS and open descriptors over time, and a Markdown page with the run's summary."""

import argparse
import datetime
import os
import platform
import subprocess
import sys
from lib.doc_paths import doc_paths  # scripts/lib, beside this script


def plot(samples, png):
    with open(samples) as csv:
        header = csv.readline().strip().split(",")
    names = [column[:-len("_rss_kib")] for column in header if column.endswith("_rss_kib")]
    rss = ", ".join(f"'{samples}' using 1:(${1 + 3 * i + 1}/1024) with lines lw 2 title '{n}'" for i, n in enumerate(names))
    fds = ", ".join(f"'{samples}' using 1:{1 + 3 * i + 2} with steps lw 2 title '{n}'" for i, n in enumerate(names))
    script = f"""set terminal pngcairo size 1100,700 font ",10" noenhanced
set output "{png}"
set datafile separator ","
set key autotitle columnhead outside right
set multiplot layout 2,1 title "scripts/soak.sh: resident memory and open descriptors, sampled once a second"
set grid
set ylabel "RSS (MiB)"
set yrange [0:*]
plot {rss}
set xlabel "seconds since the load started"
set ylabel "open descriptors"
plot {fds}
unset multiplot
"""
    try:
        subprocess.run(["gnuplot"], input=script.encode(), check=True, capture_output=True)
    except subprocess.CalledProcessError:  # gnuplot-nox may lack pngcairo: the plain png terminal
        subprocess.run(["gnuplot"], input=script.replace("pngcairo", "png").encode(), check=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", required=True)
    parser.add_argument("--summary", required=True)
    parser.add_argument("--png", required=True)
    parser.add_argument("--report", required=True)
    parser.add_argument("--command", required=True)
    parser.add_argument("--status", type=int, required=True)
    args = parser.parse_args()
    plot(args.samples, args.png)
    with open(args.summary) as summary:
        lines = summary.read().strip().splitlines()
    load = os.getloadavg()
    if os.environ.get("LDOEM_IN_UML"):  # scripts/uml/run.sh: the guest's own CPU and load say little
        where = ("inside User-Mode Linux (one virtual CPU) on a shared "
                 "2-core host, so CPU figures include UML's system-call overhead and waiting for the host")
    else:
        where = (f"{os.cpu_count()} cores, {platform.system()} {platform.release()}; load average at the end "
                 f"{load[0]:.1f} {load[1]:.1f} {load[2]:.1f}: the machine was shared, so CPU figures include waiting for it")
    page = [
        "# Soak test",
        "",
        f"Written by `{doc_paths(args.command)}` on {datetime.datetime.fromtimestamp(os.path.getmtime(args.samples), datetime.timezone.utc):%Y-%m-%d %H:%M} UTC",
        f"({where}; the run is wall-clock, not virtual time). Verdict: "
        + ("**passed**." if args.status == 0 else f"**failed** (exit {args.status})."),
        "",
        "What runs (`scripts/soak.sh --help`): `emud-tcp` is an ldoem-emud that TCP clients connect to,",
        "stream profiles from and drop (close, CANCEL_PROFILE, reset, mid-telegram); `ldoem-hub` serves",
        "16 clients asking STATUS, GET2DPROFILE and MOVEMOTOR; `emud-hub` is the ldoem-emud behind the",
        "hub, whose tilt stepper gets the LPT steps on a pty; `emud-can` (ldoem-emud on vcan0 behind the",
        "hub) runs only where vcan0 exists. Every reply is checked, and so are the final tilt and the",
        "LPT step count. Limits: at most +5 MiB of RSS after the warm-up, the same descriptors open",
        "when idle before and after the load. CI runs 60 s of it (docs/ci.md).",
        "",
        f"![RSS and descriptors over time]({os.path.basename(args.png)})",
        "",
        "## Figures of this run",
        "",
        *[f"- {line}" for line in lines],
        "",
    ]
    with open(args.report, "w") as out:
        out.write("\n".join(page))
    print(f"soak: wrote {args.report} and {args.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
