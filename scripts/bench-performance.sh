#!/usr/bin/env bash
# Build and run the performance benchmarks (tests/bench), then write docs/performance.md with
# the measured table, PASS/FAIL per target, the machine and its load, and this exact command.
# A missed target is reported, never turned into a failing exit status.
#
# Usage: scripts/bench-performance.sh [--build-dir DIR] [--no-build] [--min-time S] [--ratio-budget S]
#   --ratio-budget S: CPU seconds of alternating rounds per scene for the primitives-over-
#   triangles ratio (default 1.5; more rounds narrow the median's uncertainty, not the spread).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build/bench"
do_build=1
min_time=0.5
ratio_budget=1.5
. "$(dirname "$0")/lib/doc-paths.sh"
command_line=$(printf '%s' "scripts/bench-performance.sh $*" | doc_paths)
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build-dir) build="$2"; shift 2 ;;
    --no-build) do_build=0; shift ;;
    --min-time) min_time="$2"; shift 2 ;;
    --ratio-budget) ratio_budget="$2"; shift 2 ;;
    -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown argument: $1" >&2; exit 2 ;;
  esac
done

build_for_doc=$(printf '%s' " $(realpath -m --relative-to="$root" "$build")" | doc_paths | sed 's/^ //')
load_at_start="$(cut -d' ' -f1-3 /proc/loadavg)"
cpu_model="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
cores="$(nproc)"
started="$(date -u '+%Y-%m-%d %H:%M UTC')"

if [[ $do_build -eq 1 ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DLDOEM_ONLY="protocol;emulator;driver/cloud;driver/image;tests/bench" \
        -DLDOEM_BENCHMARKS=ON >/dev/null
  cmake --build "$build" -j2 --target ldoem_bench_perf ldoem_bench_rss >/dev/null
fi

# What the numbers were built with, from the build's cache.
build_kind="$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt")"
build_flags="$(sed -n "s/^CMAKE_CXX_FLAGS_${build_kind^^}:[A-Z]*=//p" "$build/CMakeCache.txt")"
build_type="${build_kind:-no build type}${build_flags:+ ($build_flags)}"
bench_dir="$build/tests/bench"
perf_json="$build/performance.json"
"$bench_dir/ldoem_bench_perf" --benchmark_min_time="$min_time" --ratio_budget_s="$ratio_budget" \
    --benchmark_out="$perf_json" --benchmark_out_format=json >&2
rss_json="$build/performance-rss.json"
{
  "$bench_dir/ldoem_bench_rss" scenes/corridor.yaml
  "$bench_dir/ldoem_bench_rss" scenes/large.yaml
} >"$rss_json"

python3 - "$perf_json" "$rss_json" "$root/docs/performance.md" <<PYTHON
import json, os, sys
perf = json.load(open(sys.argv[1]))
rss = [json.loads(line) for line in open(sys.argv[2]) if line.strip()]
runs = {b["run_name"]: b for b in perf["benchmarks"] if b.get("run_type") == "iteration"}
verdict = lambda ok: "not a target" if ok is None else ("PASS" if ok else "**FAIL**")
def mrays(x): return f"{x / 1e6:.2f}"

casters = [
    ("corridor", "scenes/corridor.yaml (6 objects)", True),
    ("random_10", "10 random primitives + floor", True),
    ("random_100", "100 random primitives + floor", True),
    ("random_1000", "1000 random primitives + floor", True),
    ("random_5000", "5000 random primitives + floor", True),
    ("mesh_100k", "large.yaml's rock: 100 800-triangle mesh + floor", False),
    ("large_yaml", "scenes/large.yaml (1000 primitives + the rock)", False),
]
summary = []
rows = []
for key, label, primitives_only in casters:
    b = runs[f"BM_Casters/{key}/iterations:1"]
    tri_ok = b["ratio_vs_triangles"] >= 1.0
    tri_ratio = (f"{b['ratio_vs_triangles']:.2f}x (IQR {b['ratio_vs_triangles_q1']:.2f}..{b['ratio_vs_triangles_q3']:.2f}, "
                 f"{int(b['ratio_rounds'])} rounds, {b['preemptions_per_round']:.1f} preemptions/round)")
    if primitives_only:
        match = f"{int(b['ode_mismatches'])} of {int(b['ode_rays_compared'])}"
        match_ok = b["ode_mismatches"] == 0
    else:
        match = (f"{int(b['ode_mismatches'])} over 1e-9 m, {int(b['ode_mismatches_over_0_1mm'])} over 0.1 mm, "
                 f"of {int(b['ode_rays_compared'])}")
        match_ok = None  # meshes: ODE's float trimesh is not the exact reference (design.md): no verdict
    summary.append((f">= 1.0x Embree triangles (median): {label}", tri_ratio, tri_ok))
    if primitives_only:
        summary.append((f"matches plain ODE: {label}", match, match_ok))
    ode_target = ""
    if key == "random_1000":
        summary.append((">= 20x plain ODE at 1000 primitives", f"{b['ratio_vs_ode']:.1f}x", b['ratio_vs_ode'] >= 20))
        ode_target = f" {verdict(b['ratio_vs_ode'] >= 20)} (>= 20x)"
    rows.append(f"| {label} | {mrays(b['embree_rays_s'])} | {mrays(b['triangle_rays_s'])} "
                f"({int(b['triangles_baseline'])} tri) | {mrays(b['ode_rays_s'])} | {tri_ratio} "
                f"{verdict(tri_ok)} | {b['ratio_vs_ode']:.1f}x{ode_target} | {match} {verdict(match_ok)} |")
caster_table = "\n".join(rows)

scan_rows = []
for key, label in [("paper_effects/paper_apex", "paper's effects, paper's apex (81 beams/rev) - the target"),
                   ("paper_effects/full_sector", "paper's effects, D4 270 deg sector (1081 beams/rev)"),
                   ("all_effects/paper_apex", "all sensor+motor effects, paper's apex"),
                   ("all_effects/full_sector", "all sensor+motor effects, 270 deg sector")]:
    b = runs[f"BM_PaperScan/{key}/real_time"]
    sim = b["simulated_s_per_scan"]
    wall_x = sim / (b["real_time"] / 1e3)
    cpu_x = sim / (b["cpu_time"] / 1e3)
    if key == "paper_effects/paper_apex":
        summary.append(("paper scan >= 100x real time (wall) with its effects", f"{wall_x:.0f}x", wall_x >= 100))
    target = verdict(wall_x >= 100) if key == "paper_effects/paper_apex" else ("(>= 100x: " + ("met" if wall_x >= 100 else "not met") + ")")
    scan_rows.append(f"| {label} | {int(b['beams_per_scan'])} | {b['real_time']:.1f} | {b['cpu_time']:.1f} | "
                     f"{wall_x:.0f}x | {cpu_x:.0f}x | {target} |")
scan_table = "\n".join(scan_rows)

d = runs["BM_EffectsOnDemand/iterations:1"]
spread = f"{d['model_over_bare_min']:.3f} .. {d['model_over_bare_max']:.3f}"
summary.append(("no effects within 5 % of bare casting (median)", f"{d['model_over_bare']:.3f} (spread {spread})",
                d['model_over_bare'] <= 1.05))
demand = (f"| {d['bare_ns_per_beam']:.1f} | {d['model_ns_per_beam']:.1f} | {d['model_over_bare']:.3f} | {spread} | "
          f"{int(d['repeats'])} | {verdict(d['model_over_bare'] <= 1.05)} |")

iso_rows = []
for size in (7, 100, 4400):
    b = runs[f"BM_IsoTp/{size}"]
    iso_rows.append(f"| {size} | {int(round(b['frames_per_message']))} | {b['frames_per_s'] / 1e6:.1f} | "
                    f"{b['bytes_per_second'] / 1e6:.0f} | {1e6 / (b['frames_per_s'] / b['frames_per_message']):.2f} |")
iso_table = "\n".join(iso_rows)

limits = {"scenes/corridor.yaml": 64, "scenes/large.yaml": 256}
rss_rows = []
for r in rss:
    limit = limits[r["scene"]]
    summary.append((f"peak RSS <= {limit} MiB: {r['scene']}", f"{r['peak_rss_mib']:.1f} MiB", r['peak_rss_mib'] <= limit))
    rss_rows.append(f"| {r['scene']} | {r['objects']} | {r['peak_rss_mib']:.1f} | {r['rss_at_start_mib']:.1f} | "
                    f"{r['rays_per_s'] / 1e6:.2f} | <= {limit} MiB {verdict(r['peak_rss_mib'] <= limit)} |")
rss_table = "\n".join(rss_rows)
summary_table = "\n".join(["| target | measured | verdict |", "|---|---|---|"] +
                          [f"| {t} | {m} | {verdict(ok)} |" for t, m, ok in summary])

template = open("$root/scripts/bench-performance.sh").read().split("#BEGIN-TEMPLATE\n", 1)[1].split("#END-TEMPLATE", 1)[0]
text = (template.replace("@COMMAND@", "$command_line".strip()).replace("@CORES@", "$cores").replace("@BUILD@", "$build_for_doc").replace("@BUILD_TYPE@", "$build_type")
        .replace("@CPU@", "$cpu_model").replace("@LOAD@", "$load_at_start").replace("@DATE@", "$started")
        .replace("@MIN_TIME@", "$min_time").replace("@RATIO_BUDGET@", "$ratio_budget").replace("@CASTERS@", caster_table).replace("@SCANS@", scan_table)
        .replace("@DEMAND@", demand).replace("@ISOTP@", iso_table).replace("@RSS@", rss_table).replace("@SUMMARY@", summary_table))
open(sys.argv[3], "w").write(text)
PYTHON
echo "wrote docs/performance.md" >&2
exit 0

# The report's text; @NAMES@ are filled in by the Python above.
#BEGIN-TEMPLATE
# Performance

Measured by `scripts/bench-performance.sh`; every number below comes from one run of it. Speed
targets live only here and in the benchmarks (`tests/bench`), never in unit tests. The
accuracy each speed buys is in [accuracy-vs-time.md](accuracy-vs-time.md).

## The run

- Command: `@COMMAND@` (build `@BUILD@`: @BUILD_TYPE@, g++ 12; without `--no-build` the script
  configures it with `-DLDOEM_ONLY="protocol;emulator;driver/cloud;driver/image;tests/bench"`; then it runs
  `ldoem_bench_perf --benchmark_min_time=@MIN_TIME@ --ratio_budget_s=@RATIO_BUDGET@` and `ldoem_bench_rss` per scene).
- Machine: @CORES@ cores, `@CPU@`, load average at the start `@LOAD@` (@DATE@). The machine was
  shared with other jobs compiling at the time, so absolute wall-clock figures are pessimistic.
  Ratios are therefore measured inside one benchmark, by interleaved rounds timed in thread CPU
  time (`tests/bench/support/measure.hpp`), so time spent descheduled does not count and a slow
  phase of the machine hits every contender alike. Primitives against triangles (a target within
  a few per cent of 1.0): many short alternating rounds on the same rays (primitives, triangles,
  primitives, ..., about @RATIO_BUDGET@ CPU s per scene), one ratio per round; the table gives
  the median ratio (the target applies to it), its interquartile range (IQR: half of the
  rounds fall inside) and how often other processes took the core per round (involuntary
  context switches: each refills part of the caches; at a load average of 10 on 2 cores one
  whole run came out up to 30 % lower on every scene with tight IQRs, while the runs before
  and after agreed within a few per cent: trust a run taken at low preemption). Against plain ODE: 5 interleaved rounds, the fastest of each. The
  on-demand check: 15 rounds, the fastest of each, repeated. Debian's libbenchmark prints
  "Library was built as DEBUG"; that concerns the harness, not the code measured.

## Targets at a glance

@SUMMARY@

A FAIL is reported, not hidden and not turned into an error: the script always exits 0. Details
and how each figure was measured follow.

## Ray casting: rays per second, and ratios measured in the same run

Rays: the D4 sector (270 deg at 0.25 deg) at each of the paper's 121 tilts, every 8th ray
(16 351 rays, in scan order), from the scanner's pivot 0.5 m above the floor, cast to 31 m.
Contenders: ldoem's `EmbreeRayCaster` (Embree BVH over the ODE geoms' bounds, exact
double-precision primitive tests equal to ODE's answers, robust triangles); plain ODE (`OdeRayCaster`, dCollide against every geom: the reference; with many
objects it casts every k-th ray of the batch, k sized for about 0.25 s per round: the last
column gives the count); and a plain Embree scene of triangles built by
the benchmark (`tests/bench/support/triangle_caster.cpp`: every primitive tessellated, 16
segments around, planes as 2 km squares, default build quality, no robust flag, float
distances), i.e. what a simulator that gives up exact primitives would run. "Matches ODE"
compares ldoem's answer with ODE's on every ray ODE cast: same object and range within 1e-9 m.

Targets: >= 1.0x the triangle scene's throughput on every scene (issue 15: exact primitives at
least as fast as giving them up) while matching ODE's exact answers for primitives; >= 20x plain
ODE at 1000 primitives.

| scene | ldoem Embree + exact tests (M rays/s, median round) | Embree triangles (M rays/s, median round) | plain ODE (M rays/s, fastest round) | vs triangles: median of the rounds' ratios (>= 1.0x) | vs plain ODE (fastest rounds) | matches ODE |
|---|---|---|---|---|---|---|
@CASTERS@

Mesh scenes: ODE's trimesh answers in float, so ranges differ from ldoem's double-precision
recomputation by more than 1e-9 m on some rays; the 0.1 mm column shows whether any ray hit a
different surface. Those rows are not held to "matches ODE" (design.md: meshes are Embree's).

## Peak memory (getrusage ru_maxrss), beside throughput

One process per scene (`ldoem_bench_rss`): load the YAML (assimp for meshes), build the ODE geoms
and the Embree BVH, cast all 130 801 rays of the sector above (single thread, wall clock).

| scene | objects | peak RSS (MiB) | RSS before loading (MiB) | M rays/s | target |
|---|---|---|---|---|---|
@RSS@

## The paper's scan in virtual time

At the sensor + motor level (`tests/bench/support/paper_scan.hpp`; the daemon is not involved):
head at 10 Hz, horizontal apex 20 deg at 0.25 deg, vertical apex 21.6 deg at 0.18 deg (121
layers of 2 full steps), one profile per layer, 12.4 simulated seconds per scan (the approach to
the low apex included), the corridor on the Embree caster. "Paper's effects" = noise, intensity,
incidence (corridor.yaml). "All" adds mixed_pixels (7 sub-rays), motor_dynamics (ODE hinge at
1e-3 s), head_dynamics and sweep_motion. Simulated seconds per wall second are computed from the
benchmark's wall time (the target) and from its CPU time (what an idle core would give).

| scan | beams per scan | wall ms / scan | CPU ms / scan | simulated s per wall s | per CPU s | target >= 100x |
|---|---|---|---|---|---|---|
@SCANS@

## Effects only on demand

A scene that names no effect against a bare loop over the same beams (D5 ray, `cast`, 1/256 m
quantisation, constant ECHO): the SensorModel's pipeline must cost at most 5 % more. Corridor,
every second beam of the 270 deg sector at the paper's 121 tilts. One measurement is 15
interleaved rounds (each side keeps its fastest); it is repeated, and the table gives the median
ratio (the target applies to it), the smallest and largest ratio seen, and the number of
repeats. The D13 effects (waveform, snr_noise, atmosphere) are compiled in and not named here;
that their absence changes no byte is `tests/pipeline/profile_digest_test.cpp`'s job.

| bare loop (ns/beam, median) | SensorModel, no effects (ns/beam, median) | ratio (median) | spread (min .. max) | repeats | target <= 1.05 |
|---|---|---|---|---|---|
@DEMAND@

## ISO-TP through the protocol state machines

`IsoTpSender` -> `IsoTpReceiver` in memory (flow control routed back), classic CAN, unpadded,
BS 0, STmin 0; frames counted in both directions (the flow-control frame included), rates per
CPU second. 4400 bytes is about a 270 deg profile at 0.25 deg. No target; vcan through UML is
not measured here.

| message bytes | frames per message | M frames/s | MB/s of payload | us per message |
|---|---|---|---|---|
@ISOTP@
#END-TEMPLATE
