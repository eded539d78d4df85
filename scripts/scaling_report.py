#!/usr/bin/env python3
"""Writes docs/scaling.md from the JSON lines scripts/bench-scaling.sh collected from
ldoem_bench_daemon_scaling: every table below is computed here from that run, none is typed."""
import argparse
import json
import re
from pathlib import Path
from lib.doc_paths import doc_paths  # scripts/lib, beside this script

DEVICE_MEAN_LIMIT_HZ = 10800  # spec 5: mean pulse frequency limit (control/sector_table.hpp)
WORST_CASE_BEAMS_PER_S = 14400  # issue 15's worst case: the peak pulse frequency over 360 deg
SCANNERS_PER_CORE_TARGET = 200
MIB_PER_ADDED_SCANNER_TARGET = 2.0
RETURN_CODES = {0: "0 (accepted: it measures)", 1: "1 (max pulse frequency too high)",
                2: "2 (mean pulse frequency too high)", 3: "3 (sector borders not configured)",
                4: "4 (sector borders not a multiple of the step)"}


def verdict(ok, derived=False):
    word = "met" if ok else "**not met**"
    return word + " (derived)" if derived else word


def kib(mib):
    return f"{mib * 1024:.1f} KiB"


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("results")
    parser.add_argument("output")
    for name in ("command", "date", "cpu", "cores", "load-start", "load-end", "nice", "scanners", "all-scanners"):
        parser.add_argument("--" + name, required=True)
    args = parser.parse_args()
    lines = [json.loads(line) for line in Path(args.results).read_text().splitlines() if line.strip()]
    probes = [r for r in lines if r.get("probe") == "full-turn"]
    runs = [r for r in lines if "probe" not in r]
    for r in runs:
        expected = round(r["scanners"] * 20 * r["simulated_s"])
        if r["profiles"] != expected:
            raise SystemExit(f"scaling_report: {r['scene']} {r['effects']} x{r['scanners']}: "
                             f"{r['profiles']} profiles, expected {expected}")

    by_key = {}
    for r in runs:
        by_key.setdefault((r["scene"], r["effects"]), []).append(r)
    requested = {"paper": int(args.scanners), "all": int(args.all_scanners)}

    speed_rows, memory_rows, summary, large_memory = [], [], [], []
    for (scene, effects), group in by_key.items():
        one = next(r for r in group if r["scanners"] == 1)
        main_run = next(r for r in group if r["scanners"] == requested[effects])
        checks = sorted((r for r in group if r["scanners"] not in (1, requested[effects])), key=lambda r: r["scanners"])
        held = [r for r in group if r["cpu_s_per_simulated_s"] <= 1.0]
        best = max(held, key=lambda r: r["scanners"]) if held else None
        per_beam_us = main_run["cpu_s_per_simulated_s"] / (main_run["scanners"] * main_run["beams_per_s_each"]) * 1e6
        checks_text = "; ".join(f"{r['scanners']}: {r['cpu_s_per_simulated_s']:.3f}" for r in checks) or "-"
        if best is not None:
            real_time = f"**{best['scanners']}** ({best['cpu_s_per_simulated_s']:.3f} CPU s)"
            derived = best["scanners_per_core"] * best["beams_per_s_each"] / WORST_CASE_BEAMS_PER_S
            derived_text = f"{int(derived)} (derived)"
        else:
            real_time, derived_text = "none of the runs held it", "-"
        speed_rows.append(
            f"| {scene} | {effects} | {one['cpu_s_per_simulated_s']:.4f} | {main_run['scanners']} | "
            f"{main_run['cpu_s_per_simulated_s']:.3f} | {main_run['scanners_per_core']:.0f} | {per_beam_us:.3f} us | "
            f"{checks_text} | {real_time} | {derived_text} |")
        added = main_run["scanners"] - 1
        heap_added = (main_run["heap_total_mib"] - one["heap_total_mib"]) / added
        rss_added = (main_run["rss_total_mib"] - one["rss_total_mib"]) / added
        memory_rows.append(
            f"| {scene} | {effects} | {one['rss_total_mib']:.1f} | {one['heap_total_mib']:.1f} | "
            f"{main_run['scanners']} | {main_run['rss_total_mib']:.1f} | {main_run['heap_total_mib']:.1f} | "
            f"{kib(heap_added)} | {kib(rss_added)} |")
        if effects == "paper":
            count = best["scanners"] if best else 0
            summary.append((f"scanners per core in real time on one daemon thread, paper's effects, {scene}: "
                            f">= {SCANNERS_PER_CORE_TARGET}", f"{count}", count >= SCANNERS_PER_CORE_TARGET))
            if best is not None:
                derived = int(best["scanners_per_core"] * best["beams_per_s_each"] / WORST_CASE_BEAMS_PER_S)
                summary.append((f"the same at 14 400 beams/s, **derived** (the device refuses that rate), {scene}: "
                                f">= {SCANNERS_PER_CORE_TARGET}", f"{derived} (derived)",
                                derived >= SCANNERS_PER_CORE_TARGET))
        if scene == "scenes/large.yaml":
            large_memory.append((max(heap_added, rss_added), effects))

    if large_memory:
        worst, effects = max(large_memory)
        summary.append((f"memory per added scanner, scenes/large.yaml: <= {MIB_PER_ADDED_SCANNER_TARGET:g} MiB "
                        f"(the larger of heap and RSS, the worse of the effect sets: {effects})", kib(worst),
                        worst <= MIB_PER_ADDED_SCANNER_TARGET))

    probe_rows = [f"| {p['motor_hz']} Hz | {p['angle_step_ticks'] / 16:g} deg | 360 deg | {p['beams_per_s']} | "
                  f"{RETURN_CODES.get(p['trans_measure_return_code'], p['trans_measure_return_code'])} |"
                  for p in probes]
    refused = all(p["trans_measure_return_code"] == 2 for p in probes if p["beams_per_s"] > DEVICE_MEAN_LIMIT_HZ)
    summary_table = "\n".join(["| target | measured | verdict |", "|---|---|---|"] +
                              [f"| {t} | {m} | {verdict(ok, 'derived' in m)} |" for t, m, ok in summary])
    template = (Path(__file__).parent / "scaling_report_template.md").read_text()
    values = {
        "COMMAND": doc_paths(args.command.strip()), "DATE": args.date, "CPU": args.cpu, "CORES": args.cores,
        "LOAD_START": args.load_start, "LOAD_END": args.load_end, "NICE": args.nice,
        "PROBES": "\n".join(probe_rows),
        "REFUSED": ("The emulator refuses it, as the spec says the device does" if refused else
                    "**The emulator did not refuse every whole-turn configuration above 10 800 Hz: check the probe rows**"),
        "SUMMARY": summary_table, "SPEED_ROWS": "\n".join(speed_rows), "MEMORY_ROWS": "\n".join(memory_rows),
    }
    text = template
    for name, value in values.items():
        text = text.replace("@" + name + "@", str(value))
    leftover = re.findall(r"@[A-Z_]+@", text)
    if leftover:
        raise SystemExit(f"scaling_report: unfilled {leftover}")
    Path(args.output).write_text(text)


if __name__ == "__main__":
    main()
