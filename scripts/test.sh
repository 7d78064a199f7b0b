#!/usr/bin/env bash
# Installs what is missing, builds clraster and runs the test suite on every OpenCL device present
# (`clraster devices`; scripts/setup.sh installs Intel's CPU runtime beside PoCL, so there are at
# least two independent implementations):
#   1. the release build's whole suite (unit, OpenGL conformance, models, bad input, scale, examples,
#      install) on every device, in the work-group shapes the device asks for;
#   2. on every device again, in the GPU's shapes (CLRASTER_WORK_GROUP_SHAPE=wide: work-groups of many
#      work-items, local-memory tiles), the tests labelled `shapes` (tests/CMakeLists.txt): what the
#      kernels draw, i.e. conformance, fragment counts, state and program conformance, models,
#      textures and the programs' tests. The kernels' unit tests and the chunking tests pick both
#      shapes themselves; the rest (command line, bad input, examples, install) tests the host, and
#      running it twice on both devices would take CI to an hour with cold compiler caches;
#   3. every kernel under Oclgrind, which is a device of its own and checks races and bounds;
#   4. the Python package built into a virtual environment and its pytest suite, on PoCL's device;
#   5. the host code rebuilt with AddressSanitizer and UndefinedBehaviorSanitizer, running the unit
#      and bad-input tests on PoCL's device.
# Every run happens even when one before it failed; the summary names each run's device and suite,
# and the script exits non-zero if any failed, or if PoCL or Intel's runtime is not among the devices.
# Failing image tests leave reference.png, result.png and diff.png under build/test-output/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# OCL_ICD_VENDORS: the vendors directory listing PoCL and Intel's runtime, for everything below.
# An assignment first, not eval "$(...)" alone, so that set -e stops here when the set-up fails.
environment=$("$root/scripts/setup.sh" --env)
eval "$environment"
jobs=$(nproc)

# The options every test needs, set again in case a build directory was configured without them.
suite=(-DCLRASTER_BUILD_TESTS=ON -DCLRASTER_BUILD_CLI=ON -DCLRASTER_BUILD_EXAMPLES=ON)
"$root/scripts/build.sh" "$root/build" "${suite[@]}" -DCLRASTER_SANITIZE=OFF

# ---- The devices, as the tests will see them (CLRASTER_DEVICE is an index into this list) ----
# `clraster devices` prints "N: NAME (TYPE, K compute units)", then "   platform PLATFORM, VERSION, ...".
listing=$("$root/build/src/clraster" devices)
echo "$listing"
names=() platforms=() last=""
while IFS= read -r line; do
  if [[ $line =~ ^([0-9]+):\ (.*)\ \([^,]*,\ [0-9]+\ compute\ units\)$ ]]; then
    names[${BASH_REMATCH[1]}]=${BASH_REMATCH[2]}
    last=${BASH_REMATCH[1]}
  elif [[ $line =~ ^\ +platform\ (.*),\ OpenCL\  ]]; then
    platforms[$last]=${BASH_REMATCH[1]}
  fi
done <<<"$listing"

pocl="" intel=""
for i in "${!names[@]}"; do
  case "${platforms[$i]:-}" in
    "Portable Computing Language") [ -n "$pocl" ] || pocl=$i ;;
    "Intel(R) OpenCL") intel=$i ;;
    # Should an Oclgrind ICD be installed: Oclgrind runs its own tests, the kernels under its checks.
    Oclgrind) unset "names[$i]" ;;
  esac
done
# Two implementations in every run: a missing one is an error, never a silent skip.
if [ -z "$pocl" ] || [ -z "$intel" ]; then
  echo "test: error: the tests need both PoCL and Intel's CPU runtime (\"Intel(R) OpenCL\"), but" \
       "OCL_ICD_VENDORS=${OCL_ICD_VENDORS-} lists only the devices above: see scripts/setup.sh" >&2
  exit 1
fi

# ---- The runs ----
results=() failed=0
describe() { echo "device $1: ${names[$1]} (${platforms[$1]:-unknown platform})"; }
# run TITLE DEVICE|- SHAPE BUILD_DIR CTEST_ARGS...: one ctest run, with CLRASTER_DEVICE set unless
# DEVICE is -, and CLRASTER_WORK_GROUP_SHAPE set to SHAPE (device or wide).
run() {
  local title=$1 device=$2 shape=$3 dir=$4 status=0 where
  shift 4
  if [ "$device" = - ]; then where="its own device"; else where=$(describe "$device"); fi
  echo
  echo "==== test: $title on $where ===="
  SECONDS=0
  if [ "$device" = - ]; then
    (cd "$dir" && env -u CLRASTER_DEVICE CLRASTER_WORK_GROUP_SHAPE="$shape" \
       ctest --output-on-failure --no-tests=error -j "$jobs" "$@") || status=$?
  else
    (cd "$dir" && CLRASTER_DEVICE=$device CLRASTER_WORK_GROUP_SHAPE="$shape" \
       ctest --output-on-failure --no-tests=error -j "$jobs" "$@") || status=$?
  fi
  local line
  if [ $status -eq 0 ]; then line="passed"; else line="FAILED"; failed=1; fi
  line="$line  $title on $where, ${SECONDS}s"
  echo "==== test: $line ===="
  results+=("$line")
}

for i in "${!names[@]}"; do
  run "whole suite, device work-group shape (release build)" "$i" device "$root/build" -LE '^oclgrind$'
done
for i in "${!names[@]}"; do
  run "shapes-labelled tests, wide work-group shape (release build)" "$i" wide "$root/build" -L '^shapes$'
done
# Oclgrind is an OpenCL implementation of its own (tests/oclgrind_check.sh runs the program under
# it, in both shapes), so its tests run apart, with no CLRASTER_DEVICE naming a device of this list.
run "kernels under Oclgrind (release build)" - device "$root/build" -L '^oclgrind$'

# The Python package (python/): built into a virtual environment of Debian's Python with the pinned
# packages of python/requirements.txt, built without pip's isolation so that build-python/ can keep
# its build between runs (an isolated build's CMake cache names a temporary nanobind), then its pytest
# suite on PoCL's device, whose pictures are compared with the command line built above.
python_suite() {
  local venv=$root/build-python/venv
  [ -x "$venv/bin/python" ] || /usr/bin/python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --disable-pip-version-check -r "$root/python/requirements.txt" \
      -r "$root/python/requirements-ray.txt" &&
    "$venv/bin/pip" install --quiet --disable-pip-version-check --no-build-isolation \
      --config-settings=build-dir="$root/build-python/{wheel_tag}" "$root" &&
    (cd "$root" && CLRASTER_DEVICE=$pocl CLRASTER_CLI=$root/build/src/clraster \
       "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests)
}
echo
echo "==== test: Python package (pytest) on $(describe "$pocl") ===="
SECONDS=0
if python_suite; then line="passed"; else line="FAILED"; failed=1; fi
line="$line  Python package (pytest) on $(describe "$pocl"), ${SECONDS}s"
echo "==== test: $line ===="
results+=("$line")

"$root/scripts/build.sh" "$root/build-sanitize" "${suite[@]}" -DCLRASTER_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
run "unit and bad-input tests (ASan+UBSan build)" "$pocl" device "$root/build-sanitize"

echo
echo "test: summary"
printf '  %s\n' "${results[@]}"
if [ $failed -ne 0 ]; then
  echo "test: some tests FAILED (failing image tests leave their pictures under build/test-output/)"
  exit 1
fi
echo "test: all tests passed"
