#!/bin/bash
# Run one command inside User-Mode Linux, where a real SocketCAN vcan0 (and vcan1) exists, and
# return the command's own exit status. The development and CI kernels have no CAN and no GPIO
# (socket(AF_CAN) fails with EAFNOSUPPORT); the UML guest boots with the host's root file system
# through hostfs, so it sees the same binaries, build tree and files.
#
# Usage:
#   scripts/uml/run.sh [OPTIONS] 'SHELL COMMAND'     (one argument: run by bash -c)
#   scripts/uml/run.sh [OPTIONS] -- PROGRAM [ARG...] (argv, no shell)
# Options:
#   --timeout SECONDS  kill the guest after this long, exit 124 (default 1200)
#   --mem SIZE         guest memory, UML mem= syntax (default 1G)
#   --kernel PATH      UML kernel to boot (default: linux.uml from Debian's user-mode-linux, whose
#                      CAN modules are loaded from /usr/lib/uml/modules/<version>); e.g. the gpio-sim
#                      kernel printed by scripts/uml/build-gpio-kernel.sh, which has CAN built in
#   --gpio             set up the gpio-sim chip of D8 first (scripts/uml/gpio-sim-setup.sh; needs
#                      a --kernel with gpio-sim) and export its LDOEM_GPIO_* variables
#   --verbose          also show the guest's boot messages and the harness's own steps
#   -h, --help         this text
# Inside the guest: cwd = the caller's cwd, the caller's exported environment (PATH, HOME,
# CTEST_OUTPUT_ON_FAILURE, ...) plus LDOEM_IN_UML=1, stdin = /dev/null, lo up, vcan0 and vcan1 up,
# /proc, /sys and /dev/pts mounted. The host's /tmp is NOT hidden by a tmpfs.
# Output: the command's stdout and stderr, merged, streamed on stdout as it runs.
# Exit status: the command's status; 124 on timeout; 125 when the harness itself failed (no UML
# kernel, CAN modules missing, guest setup failed, guest never reported); 128+N on SIGINT/SIGTERM.
# Examples:
#   scripts/uml/run.sh 'candump -n 1 vcan0 & sleep 0.3; cansend vcan0 123#DEADBEEF; wait'
#   scripts/uml/run.sh -- ctest --test-dir build -L vcan --output-on-failure
#   scripts/uml/run.sh --kernel "$(scripts/uml/build-gpio-kernel.sh)" --gpio -- gpioinfo ldoem-lpt
set -euo pipefail

readonly harness_failed=125
readonly timed_out=124
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

usage() { sed -n '2,29p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }
die() { echo "uml/run.sh: $*" >&2; exit "$harness_failed"; }

timeout_s=1200
mem=1G
kernel=""
gpio=0
verbose=0
while (($#)); do
  case "$1" in
    --timeout) (($# >= 2)) || die "--timeout needs a value"; timeout_s=$2; shift 2 ;;
    --timeout=*) timeout_s=${1#*=}; shift ;;
    --mem) (($# >= 2)) || die "--mem needs a value"; mem=$2; shift 2 ;;
    --mem=*) mem=${1#*=}; shift ;;
    --kernel) (($# >= 2)) || die "--kernel needs a value"; kernel=$2; shift 2 ;;
    --kernel=*) kernel=${1#*=}; shift ;;
    --gpio) gpio=1; shift ;;
    --verbose) verbose=1; shift ;;
    -h|--help) usage; exit 0 ;;
    --) shift; break ;;
    -*) die "unknown option '$1' (try --help)" ;;
    *) break ;;
  esac
done
(($#)) || die "no command given (try --help)"
[[ $timeout_s =~ ^[1-9][0-9]*$ ]] || die "--timeout wants whole seconds > 0, got '$timeout_s'"
[[ $mem =~ ^[1-9][0-9]*[KMG]?$ ]] || die "--mem wants a size like 512M or 1G, got '$mem'"

# --- the kernel and, for the stock kernel, its CAN modules ------------------------------------
moddir=""
if [[ -z $kernel ]]; then
  kernel=$(command -v linux.uml || true)
  [[ -n $kernel ]] || die "no linux.uml on PATH: apt-get install -y user-mode-linux"
  moddir=$(ls -d /usr/lib/uml/modules/*/ 2>/dev/null | sort -V | tail -n 1)
  moddir=${moddir%/}
  [[ -n $moddir ]] || die "no /usr/lib/uml/modules/<version>: reinstall user-mode-linux"
  for m in drivers/net/can/dev/can-dev net/can/can net/can/can-raw net/can/can-bcm drivers/net/can/vcan; do
    [[ -r $moddir/kernel/$m.ko ]] || die "CAN module $moddir/kernel/$m.ko is missing"
  done
else
  [[ -x $kernel ]] || die "--kernel $kernel is not an executable file"
  kernel=$(cd "$(dirname "$kernel")" && pwd)/$(basename "$kernel")
  # A custom kernel normally has CAN built in; its modules (if any) would not match the stock ones.
fi
if ((gpio)) && [[ ! -x $here/gpio-sim-setup.sh ]]; then
  die "$here/gpio-sim-setup.sh is missing"
fi

# --- a private work folder on the host; the guest sees it through hostfs ----------------------
work=$(mktemp -d "${TMPDIR:-/tmp}/ldoem-uml.XXXXXX")
work=$(cd "$work" && pwd -P)
uml_pid=""
watchdog_pid=""
filter_pid=""

kill_group() {  # $1: the leader of a process group we created with setsid
  [[ -n $1 ]] || return 0
  kill -KILL -- "-$1" 2>/dev/null || kill -KILL "$1" 2>/dev/null || true
}
cleanup() {
  kill_group "$uml_pid"
  if [[ -n $uml_pid ]]; then wait "$uml_pid" 2>/dev/null || true; fi  # reap quietly: no job notice
  kill_group "$watchdog_pid"
  if [[ -n $filter_pid ]]; then wait "$filter_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# The caller's exported environment, minus what belongs to this shell or to the host session.
{
  while IFS= read -r name; do
    case "$name" in
      PWD|OLDPWD|SHLVL|_|BASHOPTS|SHELLOPTS|BASH_*|HOSTNAME|TERM|COLUMNS|LINES) continue ;;
    esac
    printf 'export %s=%q\n' "$name" "${!name}"
  done < <(compgen -e)
  echo "export LDOEM_IN_UML=1"
} > "$work/env"

if (($# == 1)) && [[ ${1:-} != -- ]]; then
  printf '%s\n' "$1" > "$work/command"
else
  printf 'exec' > "$work/command"
  printf ' %q' "$@" >> "$work/command"
  printf '\n' >> "$work/command"
fi

cwd=$(pwd -P)
marker="ldoem-uml-${work##*.}"   # brackets the command's output on the console
caller_has_tty=0
[[ -t 1 ]] && caller_has_tty=1
# Guest PID 1. It must never exit (that panics the guest): every path ends in power_off.
cat > "$work/init" <<INIT
#!/bin/bash
export PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
work=$(printf %q "$work")
setup_failed() { echo "\$*" > "\$work/setup-error"; power_off; }
power_off() {
  sync
  # systemctl's forced power-off calls reboot(2) directly; sysrq is the fallback.
  poweroff -f -f >/dev/null 2>&1
  echo o > /proc/sysrq-trigger 2>/dev/null
  sleep 5; exit 1
}
stty -onlcr 2>/dev/null   # keep the command's bytes as they are: no CR added before LF
mount -t proc proc /proc || setup_failed "mount /proc failed"
mount -t sysfs sysfs /sys || setup_failed "mount /sys failed"
# devtmpfs gives the guest's own device nodes (/dev/gpiochipN); it lacks what udev/systemd would
# add on a normal system, so add the pieces programs expect.
grep -q ' /dev devtmpfs' /proc/mounts || mount -t devtmpfs devtmpfs /dev 2>/dev/null
mkdir -p /dev/pts /dev/shm
mount -t devpts -o ptmxmode=0666,mode=0620 devpts /dev/pts || setup_failed "mount /dev/pts failed"
mount -t tmpfs -o mode=1777 tmpfs /dev/shm 2>/dev/null
[ -e /dev/fd ] || ln -s /proc/self/fd /dev/fd
[ -e /dev/stdin ] || ln -s /proc/self/fd/0 /dev/stdin
[ -e /dev/stdout ] || ln -s /proc/self/fd/1 /dev/stdout
[ -e /dev/stderr ] || ln -s /proc/self/fd/2 /dev/stderr
ip link set lo up || setup_failed "ip link set lo up failed"
moddir=$(printf %q "$moddir")
if [ ! -d /proc/net/can ] && [ -n "\$moddir" ]; then
  for m in drivers/net/can/dev/can-dev net/can/can net/can/can-raw net/can/can-bcm drivers/net/can/vcan; do
    insmod "\$moddir/kernel/\$m.ko" || setup_failed "insmod \$moddir/kernel/\$m.ko failed (guest kernel \$(uname -r))"
  done
fi
[ -d /proc/net/can ] || setup_failed "the guest kernel \$(uname -r) has no CAN (no /proc/net/can)"
for dev in vcan0 vcan1; do
  { ip link add dev \$dev type vcan && ip link set \$dev up; } || setup_failed "creating \$dev failed"
done
if [ $gpio = 1 ]; then
  $(printf %q "$here/gpio-sim-setup.sh") "\$work/gpio-env" || setup_failed "gpio-sim setup failed"
fi
. "\$work/env"
[ -f "\$work/gpio-env" ] && . "\$work/gpio-env"
cd $(printf %q "$cwd") || setup_failed "cd $(printf %q "$cwd") failed in the guest"
echo started > "\$work/started"
echo $marker-begin
if [ $caller_has_tty = 1 ]; then
  bash "\$work/command" </dev/null
  rc=\$?
else
  # The caller's stdout is a pipe or file: give the command one too (the guest console is a tty),
  # so it buffers and colours its output as it would on the host (no escape codes in CI logs).
  bash "\$work/command" </dev/null 2>&1 | cat
  rc=\${PIPESTATUS[0]}
fi
echo $marker-end
echo \$rc > "\$work/rc.tmp" && mv "\$work/rc.tmp" "\$work/rc"
power_off
INIT
chmod +x "$work/init"

# --- boot ---------------------------------------------------------------------------------------
mkfifo "$work/console"
if ((verbose)); then
  cat < "$work/console" &
else
  # Before the command starts and after it ends, drop the boot and power-off noise that UML
  # prints even with "quiet"; the command's own output passes untouched (only the marker lines
  # that bracket it are removed).
  awk -v begin="$marker-begin" -v end="$marker-end" '
    BEGIN { noise = "^(SELinux|mmapper_init|Failed to initialize ubd|reboot: |sysrq: |NR_IRQS|.*epollctl add err fd)" }
    $0 == begin { inside = 1; next }
    # The command may end without a newline: the end marker then trails its last line.
    inside && substr($0, length($0) - length(end) + 1) == end {
      printf "%s", substr($0, 1, length($0) - length(end)); fflush(); inside = 0; next
    }
    inside || $0 !~ noise { print; fflush() }
  ' < "$work/console" &
fi
filter_pid=$!

started_s=$SECONDS
# setsid: UML and every host process it forks share one new process group we can kill at once.
setsid "$kernel" "mem=$mem" root=/dev/root rootfstype=hostfs hostfs=/ rw "init=$work/init" \
  "uml_dir=$work" umid=guest quiet con=null con0=fd:0,fd:1 < /dev/null > "$work/console" 2>&1 &
uml_pid=$!
setsid bash -c "sleep $timeout_s; touch '$work/timed-out'; kill -KILL -- -$uml_pid 2>/dev/null" \
  < /dev/null > /dev/null 2>&1 &
watchdog_pid=$!
disown "$watchdog_pid"   # its death by our kill is expected: no job notice

uml_status=0
wait "$uml_pid" 2>/dev/null || uml_status=$?
kill_group "$uml_pid"
uml_pid=""
kill_group "$watchdog_pid"
watchdog_pid=""
wait "$filter_pid" 2>/dev/null || true
filter_pid=""
((verbose)) && echo "uml/run.sh: guest ran $((SECONDS - started_s)) s, UML exit $uml_status" >&2

if [[ -e $work/timed-out ]]; then
  echo "uml/run.sh: timed out after $timeout_s s; the guest was killed" >&2
  exit "$timed_out"
fi
if [[ -f $work/setup-error ]]; then
  die "guest setup failed: $(cat "$work/setup-error")"
fi
if [[ ! -f $work/rc ]]; then
  if [[ -f $work/started ]]; then
    die "the command started but the guest never reported its exit status (UML exit $uml_status; guest out of memory or panic? try --verbose)"
  fi
  die "the guest never reported (UML exit $uml_status; kernel $kernel did not boot? try --verbose)"
fi
rc=$(cat "$work/rc")
[[ $rc =~ ^[0-9]+$ ]] || die "the guest reported a bad exit status '$rc'"
exit "$rc"
