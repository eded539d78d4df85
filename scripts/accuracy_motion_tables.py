"""The D12 rows of docs/accuracy-vs-time.md (scripts/accuracy-vs-time imports them): per-beam
time against one snapshot per revolution, and the ODE world step. `runs` maps benchmark names to
the fastest repetition's JSON record, as accuracy-vs-time's fastest_runs makes it."""


def _setting(name):
    parts = name.split("/")
    return parts[1] if len(parts) > 1 else name


def _fmt(value, digits=3):
    if value == 0:
        return "0"
    if abs(value) >= 100:
        return f"{value:.0f}"
    if abs(value) >= 0.01:
        return f"{value:.{digits}g}"
    return f"{value:.2e}"


def _find(runs, prefix):
    return [(name, bench) for name, bench in runs.items() if name.startswith(prefix)]


def skew_table(runs):
    lines = ["| beam time | RMS skew error (mm) | max (mm) | CPU us / revolution | cost vs per_beam |",
             "|---|---|---|---|---|"]
    base = next(b for n, b in runs.items() if n.startswith("BM_SkewKnob/per_beam"))["us_per_revolution"]
    for name, b in _find(runs, "BM_SkewKnob/"):
        lines.append(f"| {_setting(name)} | {_fmt(b['rms_error_mm'])} | {_fmt(b['max_error_mm'])} | "
                     f"{_fmt(b['us_per_revolution'])} | {b['us_per_revolution'] / base:.2f}x |")
    return "\n".join(lines)


def world_step_table(runs):
    lines = ["| world_step_s | falling: max error (mm) | rolling: max error (mm) | CPU ms / simulated s | "
             "cost vs 1e-2 |", "|---|---|---|---|---|"]
    base = next(b for n, b in runs.items() if n.startswith("BM_WorldStep/1e-2"))["cpu_s_per_simulated_s"]
    for name, b in _find(runs, "BM_WorldStep/"):
        lines.append(f"| {_setting(name)} | {_fmt(b['fall_max_error_mm'])} | {_fmt(b['roll_max_error_mm'])} | "
                     f"{_fmt(1e3 * b['cpu_s_per_simulated_s'])} | {b['cpu_s_per_simulated_s'] / base:.1f}x |")
    return "\n".join(lines)


