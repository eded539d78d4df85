#!/usr/bin/env bash
# Build and run ldoem_bench_scaling (tests/bench/scaling_main.cpp), then write docs/scaling.md:
# scanners per core in real time and memory per added scanner when scanners share one scene
# world, for the corridor and large.yaml, with the paper's effects and with every effect on,
# plus the machine, its load and this exact command. A missed target is reported, never turned
# into a failing exit status.
#
# Usage: scripts/bench-scaling.sh [--build-dir DIR] [--no-build] [--scanners N]
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build/bench"
do_build=1
scanners=201
command_line="scripts/bench-scaling.sh $*"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build-dir) build="$2"; shift 2 ;;
    --no-build) do_build=0; shift ;;
    --scanners) scanners="$2"; shift 2 ;;
    --help|-h) sed -n '2,9p' "$0"; exit 0 ;;
    *) echo "unknown argument: $1" >&2; exit 2 ;;
  esac
done

load_at_start="$(cut -d' ' -f1-3 /proc/loadavg)"
cpu_model="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
started="$(date -u '+%Y-%m-%d %H:%M UTC')"

if [[ $do_build -eq 1 ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DLDOEM_ONLY="protocol;emulator;driver/cloud;tests/bench" \
        -DLDOEM_BENCHMARKS=ON >/dev/null
  cmake --build "$build" -j2 --target ldoem_bench_scaling >/dev/null
fi

bench="$build/tests/bench/ldoem_bench_scaling"
results="$build/scaling.json"
cd "$root"
{
  timeout 600 "$bench" scenes/corridor.yaml paper "$scanners"
  timeout 600 "$bench" scenes/corridor.yaml all 21
  timeout 600 "$bench" scenes/large.yaml paper "$scanners"
  timeout 600 "$bench" scenes/large.yaml all 21
} >"$results"

python3 - "$results" "$root/docs/scaling.md" <<PYTHON
import json, sys
runs = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
verdict = lambda ok: "PASS" if ok else "**FAIL**"
rows, summary = [], []
for r in runs:
    rows.append(f"| {r['scene']} | {r['effects']} | {r['scanners']} | {r['cpu_s_per_simulated_s'] * 100:.1f} % | "
                f"{r['scanners_per_core']:.0f} | {r['rss_one_mib']:.1f} | {r['rss_all_mib']:.1f} | "
                f"{r['mib_per_added_scanner'] * 1024:.1f} KiB | {r['heap_mib_per_added_scanner'] * 1024:.1f} KiB |")
    if r['effects'] == 'paper':
        summary.append((f"scanners per core in real time, paper's effects, {r['scene']}: >= 200",
                        f"{r['scanners_per_core']:.0f}", r['scanners_per_core'] >= 200))
    if r['effects'] == 'paper' and r['scene'] == 'scenes/large.yaml':
        worst = max(r['mib_per_added_scanner'], r['heap_mib_per_added_scanner'])
        summary.append(("memory per added scanner, scenes/large.yaml: <= 2 MiB (the larger of RSS and heap)",
                        f"{worst * 1024:.1f} KiB", worst <= 2.0))
summary_table = "\n".join(["| target | measured | verdict |", "|---|---|---|"] +
                          [f"| {t} | {m} | {verdict(ok)} |" for t, m, ok in summary])
template = open("$root/scripts/bench-scaling.sh").read().split("#BEGIN-TEMPLATE\n", 1)[1].split("#END-TEMPLATE", 1)[0]
text = (template.replace("@COMMAND@", "$command_line".strip()).replace("@CPU@", "$cpu_model")
        .replace("@LOAD@", "$load_at_start").replace("@DATE@", "$started").replace("@SUMMARY@", summary_table)
        .replace("@ROWS@", "\n".join(rows)))
open(sys.argv[2], "w").write(text)
PYTHON
echo "wrote docs/scaling.md" >&2
exit 0

# The report's text; @NAMES@ are filled in by the Python above.
#BEGIN-TEMPLATE
# Scaling: many scanners, one core, many machines

Measured by `scripts/bench-scaling.sh`; every number below comes from one run of it
(`@COMMAND@`, @DATE@, `@CPU@`, load average at the start `@LOAD@`; the machine was shared
with other jobs, and the figures are thread CPU time, so time spent descheduled does not count).

## Scanners per core in real time

The worst case the device allows: 14 400 beams/s per scanner (20 Hz, 0.5 deg over the full
360 deg, 720 beams per revolution), every revolution measured, 2 simulated seconds.
`ldoem_bench_scaling` (tests/bench/scaling_main.cpp) builds the scene's world once (ODE geoms and
Embree BVH, `plant::SceneWorld`) and one `plant::ScenePlant` per scanner on it (sensor model,
tilt plate, head model: what each device instance of the daemon adds), then measures every
scanner's revolutions on one thread. "CPU per simulated second" is for all the scanners
together; scanners per core = scanners / that.

What this does not include, and why: it runs below the daemon. The control unit's telegram
encoding and the socket writes per profile are not in it (for scale: one whole daemon, measuring
included, streams about 4000 profiles/s of 540 points over TCP in virtual time,
[latency.md](latency.md)), and every scanner stands at the scene's pivot. One `ldoem-emud` now
holds several scanners (a `scanners:` list, docs/scenes.md "Several scanners");
`ldoem_bench_daemon_scaling` measures that whole daemon on its loop thread, but this report does
not run it yet, so the table below is the sharing measured on the pieces a daemon shares.

@SUMMARY@

| scene | effects | scanners | CPU per simulated second | scanners per core | RSS with 1 scanner (MiB) | RSS with all (MiB) | RSS per added scanner | heap per added scanner |
|---|---|---|---|---|---|---|---|---|
@ROWS@

"paper" = noise, intensity, incidence (corridor.yaml's own). "all" adds mixed_pixels (7 sub-rays
per beam), motor_dynamics (the tilt hinge stepped in ODE), head_dynamics and sweep_motion.

## Memory per added scanner

RSS is read from /proc/self/statm after the world and the first scanner, and again after all of
them; RSS misses objects that land in pages the scene's loading already touched and freed, so
the heap's bytes in use (glibc mallinfo2) are given too. The scene, its ODE geoms and its BVH exist once; a scanner adds its plant only (a
daemon's per-scanner control unit, flash image and endpoints are not measured here). Today each scanner is its
own `ldoem-emud`, which holds its own copy of the scene: about 80 MiB each for large.yaml
([performance.md](performance.md), peak RSS).

## Past one machine

Scaling past one machine goes through existing tools, not a home-made layer: one `ldoem-emud`
per scanner (or per scanner group, once a daemon holds several), each with its own scene file,
flash image, TCP port and either its own CAN interface or its own CAN identifier pair on a shared
bus (`--can-ids`, D1).

- systemd: `scripts/systemd/ldoem-emud@.service` is a template unit; each instance reads
  `/etc/ldoem/<instance>.env` (example: `scripts/systemd/ldoem-emud.env.example`) for its scene,
  CAN interface, identifier pair and TCP port, keeps its flash under `/var/lib/ldoem/<instance>.flash`,
  and stops cleanly on SIGTERM (exit 143, flash saved). `systemctl enable --now
  ldoem-emud@cell1 ldoem-emud@cell2` starts two.
- Container orchestrators: one container per instance, the same four settings as environment
  variables; CAN needs the host's interface in the container's network namespace (for vcan, a
  `vxcan` pair per container, created by the host's network plugin), TCP a published port per
  instance. Per the measurements above, one core carries a few hundred scanners' physics, so a
  node's limit is its cores and, per daemon, the scene's memory (one copy per daemon, not per
  scanner, once daemons hold several scanners).
- Identifier plan for one shared CAN bus: instance k answers on 0x6C0 + 2k / 0x6C1 + 2k (11-bit,
  D1); the host side opens the matching pair per scanner.
#END-TEMPLATE
