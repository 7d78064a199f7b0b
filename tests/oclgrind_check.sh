#!/usr/bin/env bash
# Runs a program under Oclgrind with its data-race, memory and API checks; fails when the program
# fails or Oclgrind reports anything.
set -uo pipefail
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# (Not --uninitialized: Oclgrind 21.10's uninitialized-value plugin crashes on atomic_max.)
oclgrind --data-races --check-api "$@" >"$log" 2>&1
status=$?
cat "$log"
if [ $status -ne 0 ]; then
  echo "oclgrind_check: the program exited with $status" >&2
  exit 1
fi
# Oclgrind's reports name the kernel and work-item ("Kernel: ...", "Work-item: ...").
if grep -qE "Invalid (read|write)|[Dd]ata race|Uninitialized|Oclgrind -|Kernel: " "$log"; then
  echo "oclgrind_check: Oclgrind reported errors" >&2
  exit 1
fi
