#!/usr/bin/env bash
# Installs what is missing, builds clraster and runs the test suite on every OpenCL device present
# (`clraster devices`; scripts/setup.sh installs Intel's CPU runtime beside PoCL, so there are at
# least two independent implementations):
#   1. the release build's whole suite on PoCL's device (unit, OpenGL conformance, models, bad input,
#      scale, examples, install), then every kernel under Oclgrind, which is a device of its own;
#   2. on every other device, the tests labelled `device` (tests/CMakeLists.txt): conformance with
#      the fragment counts, state conformance, program conformance and the programs' tests. The
#      whole suite again on each would take CI past its time: Intel's compiler takes ~20 s a program
#      on a cold cache;
#   3. the host code rebuilt with AddressSanitizer and UndefinedBehaviorSanitizer, running the unit
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
# run TITLE DEVICE|- BUILD_DIR CTEST_ARGS...: one ctest run, with CLRASTER_DEVICE set unless DEVICE is -.
run() {
  local title=$1 device=$2 dir=$3 status=0 where
  shift 3
  if [ "$device" = - ]; then where="its own device"; else where=$(describe "$device"); fi
  echo
  echo "==== test: $title on $where ===="
  SECONDS=0
  if [ "$device" = - ]; then
    (cd "$dir" && env -u CLRASTER_DEVICE ctest --output-on-failure --no-tests=error -j "$jobs" "$@") || status=$?
  else
    (cd "$dir" && CLRASTER_DEVICE=$device ctest --output-on-failure --no-tests=error -j "$jobs" "$@") || status=$?
  fi
  local line
  if [ $status -eq 0 ]; then line="passed"; else line="FAILED"; failed=1; fi
  line="$line  $title on $where, ${SECONDS}s"
  echo "==== test: $line ===="
  results+=("$line")
}

# Oclgrind is an OpenCL implementation of its own (tests/oclgrind_check.sh runs the program under
# it), so its tests run apart, with no CLRASTER_DEVICE naming a device of this list.
run "whole suite (release build)" "$pocl" "$root/build" -LE '^oclgrind$'
run "kernels under Oclgrind (release build)" - "$root/build" -L '^oclgrind$'
for i in "${!names[@]}"; do
  [ "$i" = "$pocl" ] && continue
  run "device tests: conformance, fragment counts, state, programs (release build)" "$i" "$root/build" -L '^device$'
done

"$root/scripts/build.sh" "$root/build-sanitize" "${suite[@]}" -DCLRASTER_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
run "unit and bad-input tests (ASan+UBSan build)" "$pocl" "$root/build-sanitize"

echo
echo "test: summary"
printf '  %s\n' "${results[@]}"
if [ $failed -ne 0 ]; then
  echo "test: some tests FAILED (failing image tests leave their pictures under build/test-output/)"
  exit 1
fi
echo "test: all tests passed"
