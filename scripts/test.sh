#!/usr/bin/env bash
# Installs what is missing, builds clraster and runs the whole test suite:
#   1. every test of the release build (unit, OpenGL conformance, models, bad input, Oclgrind);
#   2. the host code rebuilt with AddressSanitizer and UndefinedBehaviorSanitizer, running the unit
#      and bad-input tests.
# Failing image tests leave reference.png, result.png and diff.png under build/test-output/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh"

# The options every test needs, set again in case a build directory was configured without them.
suite=(-DCLRASTER_BUILD_TESTS=ON -DCLRASTER_BUILD_CLI=ON -DCLRASTER_BUILD_EXAMPLES=ON)
"$root/scripts/build.sh" "$root/build" "${suite[@]}" -DCLRASTER_SANITIZE=OFF
(cd "$root/build" && ctest --output-on-failure --no-tests=error -j "$(nproc)")

"$root/scripts/build.sh" "$root/build-sanitize" "${suite[@]}" -DCLRASTER_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
(cd "$root/build-sanitize" && ctest --output-on-failure --no-tests=error -j "$(nproc)")
echo "test: all tests passed"
