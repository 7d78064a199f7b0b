#!/usr/bin/env bash
# Installs what is missing, builds clraster and renders the built-in demo scene to demo.png.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh" --packages-only   # one device is enough: not Intel's runtime (700 MB)
CLRASTER_TARGET=clraster_cli "$root/scripts/build.sh"
"$root/build/src/clraster" render --output "$root/demo.png" --size 1280x720 --stats
echo "demo: wrote $root/demo.png"
