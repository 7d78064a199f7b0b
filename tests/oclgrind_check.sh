#!/usr/bin/env bash
# Runs oclgrind_scene under Oclgrind with its data-race, memory and API checks, and on the default
# device; fails when either run fails, Oclgrind reports anything, or the two drew different bytes.
#   oclgrind_check.sh OCLGRIND_SCENE [wide]
set -uo pipefail
scene=$1
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! "$scene" "$@" "$work/device" >"$work/device.log" 2>&1; then
  cat "$work/device.log"
  echo "oclgrind_check: the scene failed on the default device" >&2
  exit 1
fi
cat "$work/device.log"
# (Not --uninitialized: Oclgrind 21.10's uninitialized-value plugin crashes on atomic_max.)
# Oclgrind is its own platform, with one device: a CLRASTER_DEVICE meant for the default run must
# not pick another.
env -u CLRASTER_DEVICE oclgrind --data-races --check-api "$scene" "$@" "$work/oclgrind" >"$work/oclgrind.log" 2>&1
status=$?
cat "$work/oclgrind.log"
if [ $status -ne 0 ]; then
  echo "oclgrind_check: the program exited with $status under Oclgrind" >&2
  exit 1
fi
# Oclgrind's reports name the kernel and work-item ("Kernel: ...", "Work-item: ...").
if grep -qE "Invalid (read|write)|[Dd]ata race|Uninitialized|Oclgrind -|Kernel: " "$work/oclgrind.log"; then
  echo "oclgrind_check: Oclgrind reported errors" >&2
  exit 1
fi
# Oclgrind has OpenCL's minimum of local memory, which tiles of 32x32 given explicitly do not fit.
if ! grep -q "refused 32x32 tiles: .*local memory; device Oclgrind Simulator has 32768" "$work/oclgrind.log"; then
  echo "oclgrind_check: tiles of 32x32 were not refused for their local memory under Oclgrind" >&2
  exit 1
fi
# Both runs drew every target (oclgrind_scene checks that); they must have drawn the same bytes.
different=0
for file in "$work"/device/*.bin; do
  name=$(basename "$file")
  if ! cmp -s "$file" "$work/oclgrind/$name"; then
    echo "oclgrind_check: $name differs between the default device and Oclgrind" >&2
    different=1
  fi
done
exit $different
