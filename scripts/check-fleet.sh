#!/usr/bin/env bash
# The fleet, tested with podman (docs/scaling.md, "The fleet"):
#   1. deploy/kubernetes/fleet.yaml is what deploy/kubernetes/render.py writes (not stale);
#   2. the image (scripts/build-image.sh; cached);
#   3. `podman kube play` of N = 3 scanner Pods and the hub Pod (render.py podman: the
#      StatefulSet's containers as Pods, on loopback ports), each scanner ready by its probe;
#      and the probe fails while a scanner's daemon is stopped (SIGSTOP: it still accepts);
#   4. a scan through the hub from each scanner to a PLY (ldoem-scan --hub, in parallel), each
#      cloud checked: layers, point count, the corridor's wall and cylinder fit;
#   5. one scanner's container killed (SIGKILL): the hub reports the device's FAULT, and after
#      the container is started again, INITIALIZE through the hub answers and the hub reports
#      RECOVERED;
#   6. a clean stop (SIGTERM: exit 143, every flash saved on its volume), then everything
#      removed: pods, containers, volumes; of the images only the cached ldoem image stays.
# Every wait is bounded. Exit 0 all passed, 1 a check failed, 2 usage error; when podman cannot
# run a container at all on this machine it says why and exits 0 without testing (SKIPPED).
set -euo pipefail

usage() {
  cat <<'EOF'
usage: scripts/check-fleet.sh [--build-dir DIR] [--deb FILE] [--scanners N]

Builds the image, runs N (default 3) emulated scanners and the hub with `podman kube play`,
scans through the hub from each scanner, kills one and checks the hub reports it and recovers,
then removes everything it made but the cached image.

  --build-dir DIR   the built programs (default build/default): the .deb for the image, and
                    ldoem-scan, the client that scans through the hub
  --deb FILE        make the image from this .deb instead of running cpack in DIR
  --scanners N      how many scanners (2..8, default 3)

Environment: LDOEM_CACHE (the image's cache, scripts/build-image.sh). Needs root and podman.
EOF
}

cd "$(dirname "$0")/.."
tool=check-fleet
build_dir=build/default
deb=""
scanners=3
while [[ $# -gt 0 ]]; do
  case $1 in
    --build-dir) build_dir=${2:?--build-dir needs a folder}; shift 2 ;;
    --deb) deb=${2:?--deb needs a file}; shift 2 ;;
    --scanners) scanners=${2:?--scanners needs a number}; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "$tool: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done
[[ $scanners =~ ^[2-8]$ ]] || { echo "$tool: --scanners must be 2..8" >&2; exit 2; }
started=$SECONDS
say() { printf '%s: [%3d s] %s\n' "$tool" $((SECONDS - started)) "$*"; }
fail() { echo "$tool: FAILED: $*" >&2; exit 1; }

scan=$build_dir/driver/scan/ldoem-scan
[[ -x $scan ]] || fail "$scan is not built (the client that scans through the hub)"
command -v podman >/dev/null || fail "podman is missing (scripts/install-deps.sh installs it)"

say "deploy/kubernetes/fleet.yaml against render.py"
rendered=$(python3 deploy/kubernetes/render.py kubernetes)
[[ $rendered == "$(cat deploy/kubernetes/fleet.yaml)" ]] ||
  fail "deploy/kubernetes/fleet.yaml is stale: run deploy/kubernetes/render.py kubernetes --out deploy/kubernetes/fleet.yaml"

say "image (scripts/build-image.sh)"
image_started=$SECONDS
if [[ -n $deb ]]; then
  image=$(scripts/build-image.sh --deb "$deb" | tail -n 1)
else
  image=$(scripts/build-image.sh --build-dir "$build_dir" | tail -n 1)
fi
image_seconds=$((SECONDS - image_started))
image_mb=$(( $(podman image inspect --format '{{.Size}}' "$image") / 1000000 ))
say "image $image: $image_mb MB, $image_seconds s"

# Can podman run a container here at all? If not, that is the machine, not the fleet.
if ! why=$(timeout 120 podman run --rm --network none --entrypoint /bin/true "$image" 2>&1); then
  echo "$tool: SKIPPED: podman cannot run a container on this machine, so the fleet is not tested." >&2
  echo "$tool: podman run --rm $image /bin/true said: $(tail -n 3 <<<"$why")" >&2
  echo "$tool: docs/scaling.md, \"Podman on this kind of machine\", lists the settings it needs." >&2
  exit 0
fi

prefix=ldoem-fleet-check
work=$(mktemp -d "${TMPDIR:-/tmp}/ldoem-fleet.XXXXXX")
pods_file=$work/pods.yaml
images_before=$(podman images --format '{{.Repository}}:{{.Tag}}' | sort)
volumes_before=$(podman volume ls --format '{{.Name}}' | sort)
teardown() {
  if [[ -f $pods_file ]]; then
    timeout 120 podman kube down "$pods_file" >/dev/null 2>&1 || true
  fi
  # Also what an earlier, interrupted run may have left.
  podman pod ls --format '{{.Name}}' | grep "^$prefix-" | xargs -r podman pod rm --force >/dev/null 2>&1 || true
  podman volume ls --format '{{.Name}}' | grep "^$prefix-" | xargs -r podman volume rm --force >/dev/null 2>&1 || true
  # The anonymous volumes of the image's VOLUME in containers that mount nothing there (the hub).
  podman volume ls --format '{{.Name}}' | sort | comm -13 <(echo "$volumes_before") - |
    xargs -r podman volume rm --force >/dev/null 2>&1 || true
  # The pause image podman builds for pods' infra containers, if this run made it.
  podman images --format '{{.Repository}}:{{.Tag}}' | sort | comm -13 <(echo "$images_before") - |
    grep -v '^localhost/ldoem:' | xargs -r podman rmi --force >/dev/null 2>&1 || true
}
# shellcheck disable=SC2154  # status is set inside the trap
trap 'status=$?; teardown; rm -rf "$work"; exit $status' EXIT
teardown

# Loopback ports: N scanners (host protocol and LPT bridge each) and the hub, all free now.
read -r port_base hub_port < <(python3 - "$scanners" <<'EOF'
import socket, sys
n = int(sys.argv[1])
for base in range(49300, 60000, 32):
    ports = list(range(base, base + 2 * n + 1))
    try:
        socks = []
        for port in ports:
            s = socket.socket()
            s.bind(("127.0.0.1", port))
            socks.append(s)
    except OSError:
        continue
    finally:
        for s in socks:
            s.close()
    print(base + 1, base)
    break
EOF
)
[[ -n $port_base ]] || fail "no $((2 * scanners + 1)) free loopback ports found in 49300..60000"
python3 deploy/kubernetes/render.py podman --scanners "$scanners" --image "$image" --prefix "$prefix" \
  --port-base "$port_base" --hub-port "$hub_port" --out "$pods_file"

say "podman kube play: $scanners scanners and the hub"
play_started=$SECONDS
timeout 180 podman kube play "$pods_file" >"$work/play.out" 2>&1 || { cat "$work/play.out" >&2; fail "podman kube play"; }
for ((k = 0; k < scanners; ++k)); do
  port=$((port_base + 2 * k))
  deadline=$((SECONDS + 60))
  until deploy/image/ldoem-healthcheck "127.0.0.1:$port" >/dev/null 2>&1; do
    if ((SECONDS > deadline)); then
      podman logs "$prefix-scanner-$k-ldoem-emud" >&2 || true
      fail "scanner $k does not answer GET_STATUS on 127.0.0.1:$port within 60 s of kube play"
    fi
    sleep 0.2
  done
done
start_seconds=$((SECONDS - play_started))
say "all $scanners scanners answer GET_STATUS, $start_seconds s after kube play started"
# The probes as Kubernetes runs them: kube play made the livenessProbe the container's health check.
for ((k = 0; k < scanners; ++k)); do
  timeout 30 podman healthcheck run "$prefix-scanner-$k-ldoem-emud" ||
    fail "podman healthcheck run of scanner $k (its livenessProbe) did not pass"
done
timeout 30 podman healthcheck run "$prefix-hub-ldoem-hub" || fail "the hub's livenessProbe did not pass"
say "every container's livenessProbe passes (podman healthcheck run)"
# A daemon whose loop hangs still accepts connections (the kernel does): the probe must fail.
frozen=$((scanners - 1))
frozen_pid=$(podman inspect --format '{{.State.Pid}}' "$prefix-scanner-$frozen-ldoem-emud")
kill -STOP "$frozen_pid"
if deploy/image/ldoem-healthcheck "127.0.0.1:$((port_base + 2 * frozen))" >/dev/null 2>&1; then
  kill -CONT "$frozen_pid"
  fail "ldoem-healthcheck passed against scanner-$frozen's stopped daemon (SIGSTOP)"
fi
kill -CONT "$frozen_pid"
deploy/image/ldoem-healthcheck "127.0.0.1:$((port_base + 2 * frozen))" >/dev/null ||
  fail "scanner-$frozen does not answer after SIGCONT"
say "the probe fails against a stopped daemon (SIGSTOP) and passes again after SIGCONT"

say "scan through the hub from each scanner (paper's settings, 61 layers of 0.36 deg)"
pids=()
for ((k = 0; k < scanners; ++k)); do
  timeout 180 "$scan" --hub "127.0.0.1:$hub_port" --hub-device "scanner-$k" \
    --horizontal-apex 20 --horizontal-resolution 0.25 --vertical-apex 21.6 --vertical-resolution 0.36 \
    --speed 10 --out "$work/scanner-$k.ply" --fit >"$work/scan-$k.out" 2>&1 &
  pids+=($!)
done
for ((k = 0; k < scanners; ++k)); do
  wait "${pids[$k]}" || { cat "$work/scan-$k.out" >&2; fail "ldoem-scan through the hub from scanner-$k"; }
done
say "scans done"
# The corridor (scenes/corridor.yaml): wall 4.180 m away, a cylinder 0.195 m across, 0.998 m long.
for ((k = 0; k < scanners; ++k)); do
  points=$(head -c 400 "$work/scanner-$k.ply" | sed -n 's/^element vertex //p' | head -n 1)
  grep -q ' in 61 layers written' "$work/scan-$k.out" || fail "scanner-$k's scan did not write 61 layers"
  fit=$(grep -m1 '^wall distance' "$work/scan-$k.out" || true)
  echo "$tool: scanner-$k: $points points; $fit"
  awk -v points="$points" -v fit="$fit" 'BEGIN {
    n = split(fit, w, /[ ;,()]+/)
    for (i = 1; i <= n; ++i) {
      if (w[i] == "distance") wall = w[i + 1]
      if (w[i] == "diameter") diameter = w[i + 1]
      if (w[i] == "length") len = w[i + 1]
    }
    # 61 layers x 81 beams = 4941 beams; every one sees the wall or the cylinder.
    ok = points >= 4800 && points <= 4941 && wall > 4.170 && wall < 4.190 &&
         diameter > 0.185 && diameter < 0.205 && len > 0.95 && len < 1.05
    exit !ok }' || fail "scanner-$k's cloud is not the corridor (points 4800..4941, wall 4.18 +- 0.01 m, cylinder 0.195 +- 0.01 m x 0.998 +- 0.05 m)"
done

victim=$((scanners > 1 ? 1 : 0))
container=$prefix-scanner-$victim-ldoem-emud
say "kill scanner-$victim ($container, SIGKILL) and ask the hub"
timeout 30 podman kill --signal KILL "$container" >/dev/null
# podman kill returns when the signal is sent; the container's exit is recorded later by its
# cleanup process. Start it again before that and the late cleanup marks the new run as the old
# one's exit (137): podman then neither lists nor stops it (seen on a busy CI machine).
killed_code=$(timeout 30 podman wait "$container" 2>&1) || fail "podman wait $container: $killed_code"
[[ $killed_code == 137 ]] || fail "scanner-$victim exited $killed_code after SIGKILL, not 137"
python3 scripts/lib/hub_session.py "127.0.0.1:$hub_port" --timeout 30 \
  "send:1 scanner-$victim STATUS 0" "expect:1:^1 ERR (connection_closed|timeout|system) " \
  "notice:^\* OK FAULT device=scanner-$victim .*kind=connection_closed" \
  "send:2 scanner-0 STATUS 0" "expect:2:^2 OK STATUS .*mode=idle" >"$work/kill.out" 2>&1 ||
  { cat "$work/kill.out" >&2; fail "the hub did not report scanner-$victim's loss (and serve scanner-0)"; }
sed 's/^/    /' "$work/kill.out"
say "restart $container"
timeout 60 podman start "$container" >/dev/null 2>"$work/start.err" || { cat "$work/start.err" >&2; fail "podman start $container"; }
deadline=$((SECONDS + 60))
until deploy/image/ldoem-healthcheck "127.0.0.1:$((port_base + 2 * victim))" >/dev/null 2>&1; do
  ((SECONDS <= deadline)) || fail "scanner-$victim does not answer GET_STATUS within 60 s of its restart"
  sleep 0.2
done
state=$(podman inspect --format '{{.State.Status}}' "$container")
[[ $state == running ]] || fail "podman says $container is $state after its restart, though it answers"
python3 scripts/lib/hub_session.py "127.0.0.1:$hub_port" --timeout 30 \
  "send:3 scanner-$victim INITIALIZE" "expect:3:^3 OK INITIALIZE .*mode=idle" \
  "notice:^\* OK RECOVERED device=scanner-$victim" \
  "send:4 scanner-$victim STATUS 0" "expect:4:^4 OK STATUS .*source=device" >"$work/recover.out" 2>&1 ||
  { cat "$work/recover.out" >&2; fail "the hub did not recover scanner-$victim after its restart"; }
sed 's/^/    /' "$work/recover.out"
say "the hub reported the loss and recovered"

# Memory per pod: the cgroup's count (podman stats: without the page cache, so the shared
# libraries' pages are not in it) and the resident set of the container's process (VmRSS).
podman stats --no-stream --format '{{.Name}} {{.MemUsage}}' 2>/dev/null | grep "^$prefix-" | sort |
  sed "s/^/$tool: memory (cgroup): /" || true
for name in $(podman ps --format '{{.Names}}' | grep "^$prefix-.*-ldoem-" | sort); do
  pid=$(podman inspect --format '{{.State.Pid}}' "$name")
  echo "$tool: memory (VmRSS): $name $(sed -n 's/^VmRSS: *//p' "/proc/$pid/status" 2>/dev/null)"
done

say "stop (SIGTERM): every scanner exits 143 with its flash saved on its volume"
scanner_pods=()
for ((k = 0; k < scanners; ++k)); do scanner_pods+=("$prefix-scanner-$k"); done
timeout 60 podman pod stop --time 15 "${scanner_pods[@]}" \
  >/dev/null 2>"$work/stop.err" || { cat "$work/stop.err" >&2; fail "podman pod stop"; }
for ((k = 0; k < scanners; ++k)); do
  code=$(podman inspect --format '{{.State.ExitCode}}' "$prefix-scanner-$k-ldoem-emud")
  [[ $code == 143 ]] || { podman logs "$prefix-scanner-$k-ldoem-emud" | tail -n 5 >&2; fail "scanner-$k exited $code on SIGTERM, not 143"; }
  volume=$(podman volume inspect --format '{{.Mountpoint}}' "$prefix-flash-scanner-$k")
  ls "$volume"/*.flash >/dev/null 2>&1 || fail "scanner-$k's flash volume holds no .flash file"
done

say "tear down"
teardown
rm -f "$pods_file"
left=$( { podman pod ls --format '{{.Name}}'; podman ps -a --format '{{.Names}}'; } | grep "^$prefix-" || true)
left+=$(podman volume ls --format '{{.Name}}' | sort | comm -13 <(echo "$volumes_before") - || true)
[[ -z $left ]] || fail "left behind: $left"
images_after=$(podman images --format '{{.Repository}}:{{.Tag}}' | sort)
extra=$(comm -13 <(echo "$images_before") <(echo "$images_after") | grep -vxF "$image" || true)
[[ -z $extra ]] || fail "images left behind: $extra"
say "all passed: image $image_mb MB (built or found in $image_seconds s), $scanners pods ready in $start_seconds s"
