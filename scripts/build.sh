#!/usr/bin/env bash
# Configures and builds clraster (Release) into DIR (default build/), with extra CMake arguments.
# CLRASTER_TARGET=name builds only that target (the demo builds only the command line).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:-$root/build}
shift || true
cmake -S "$root" -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$dir" -j "$(nproc)" ${CLRASTER_TARGET:+--target "$CLRASTER_TARGET"}
