#!/bin/sh
# Inside the gpio-sim UML guest: create the simulated chip that stands in for the pseudo-LPT
# data register (D8), through configfs. Lines 0..7 are the data bits DATA0..DATA7; the three that
# carry meaning are named: line 0 "DIR", line 1 "CLK", line 2 "MODE".
# Tests drive a line from "outside" by writing pull-up / pull-down to
#   $LDOEM_GPIO_SIM_SYSFS/sim_gpio<N>/pull
# Idempotent: a chip that is already live is reused.
#
# Usage: gpio-sim-setup.sh [ENV_FILE]   create the chip; write its shell variables to ENV_FILE
#                                       (default: stdout):
#          LDOEM_GPIO_LABEL=ldoem-lpt   chip label (gpiod_chip_open_by_label)
#          LDOEM_GPIO_CHIP=gpiochipN    chip name (gpiod_chip_open_by_name, /dev/gpiochipN)
#          LDOEM_GPIO_SIM_SYSFS=/sys/devices/platform/gpio-sim.M/gpiochipN
#        gpio-sim-setup.sh --remove     take the chip down again
# Exit status: 0 done, 1 failed (message on stderr).
set -eu

label=ldoem-lpt
configfs=/sys/kernel/config
chip_dir=$configfs/gpio-sim/$label
bank=$chip_dir/bank0

fail() { echo "gpio-sim-setup.sh: $*" >&2; exit 1; }

grep -q " $configfs configfs" /proc/mounts || mount -t configfs configfs "$configfs" ||
  fail "cannot mount configfs on $configfs"
[ -d "$configfs/gpio-sim" ] ||
  fail "this kernel has no gpio-sim; boot the one from scripts/uml/build-gpio-kernel.sh"

if [ "${1:-}" = "--remove" ]; then
  [ -d "$chip_dir" ] || exit 0
  echo 0 > "$chip_dir/live"
  for line in "$bank"/line*; do rmdir "$line"; done
  rmdir "$bank" "$chip_dir"
  exit 0
fi

if [ ! -d "$chip_dir" ]; then
  mkdir "$chip_dir" "$bank"
  echo 8 > "$bank/num_lines"
  echo "$label" > "$bank/label"
  offset=0
  for name in DIR CLK MODE; do   # D8: DATA0 direction, DATA1 clock, DATA2 mode
    mkdir "$bank/line$offset"
    echo "$name" > "$bank/line$offset/name"
    offset=$((offset + 1))
  done
fi
[ "$(cat "$chip_dir/live")" = 1 ] || echo 1 > "$chip_dir/live" || fail "could not bring the chip live"

device=$(cat "$chip_dir/dev_name")
chip=$(cat "$bank/chip_name")
sysfs=/sys/devices/platform/$device/$chip
[ -d "$sysfs" ] || fail "no $sysfs after going live"
grep -q ' /dev devtmpfs' /proc/mounts || mount -t devtmpfs devtmpfs /dev ||
  fail "cannot mount devtmpfs on /dev (needed for /dev/$chip)"
[ -c "/dev/$chip" ] || fail "no character device /dev/$chip"

out=${1:-/dev/stdout}
{
  echo "export LDOEM_GPIO_LABEL=$label"
  echo "export LDOEM_GPIO_CHIP=$chip"
  echo "export LDOEM_GPIO_SIM_SYSFS=$sysfs"
} > "$out"
