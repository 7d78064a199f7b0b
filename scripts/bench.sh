#!/usr/bin/env bash
# Installs what is missing, builds the command line and runs its benchmark (`clraster bench`):
# fixed procedural scenes at 1920x1080 drawn by clraster and by Mesa's llvmpipe in turn. Arguments
# go to `clraster bench` (e.g. --scenes model-50k,fill-16 --frames 15 --json).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh" --packages-only   # one device is enough: not Intel's runtime (700 MB)
CLRASTER_TARGET=clraster_cli "$root/scripts/build.sh"
"$root/build/src/clraster" bench "$@"
