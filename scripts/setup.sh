#!/usr/bin/env bash
# Installs everything clraster needs to build, run and test on a bare Debian 12, non-interactively:
#   1. Debian packages (apt-get, as root or through sudo);
#   2. Intel's CPU OpenCL runtime, a second OpenCL implementation beside PoCL that the tests also run
#      on: pinned PyPI packages in a virtual environment of its own (Debian 12's pip refuses system-wide
#      installs), and an ICD vendors directory listing it with the system's drivers. About 700 MB, in
#      $CLRASTER_INTEL_OPENCL_DIR (default ${XDG_CACHE_HOME:-~/.cache}/clraster/intel-opencl).
# Idempotent and quick when everything is present, so the demo and test commands call it every time.
#   scripts/setup.sh                   both
#   scripts/setup.sh --packages-only   the Debian packages only (the demo and the benchmark use one device)
#   scripts/setup.sh --env             both, then prints `export OCL_ICD_VENDORS=...` on stdout: eval it
#                                      and the ICD loader lists PoCL and Intel's runtime (clraster devices)
# Everything else it prints goes to stderr, so that `eval "$(scripts/setup.sh --env)"` works.
set -euo pipefail
exec 3>&1 1>&2

mode=all
case "${1:-}" in
  "") ;;
  --packages-only) mode=packages ;;
  --env) mode=env ;;
  *) echo "setup: unknown option '$1' (options: --packages-only, --env)"; exit 2 ;;
esac

# ---- 1. Debian packages ----
# Checked against what the build reads (compiler dependency files, link lines, CMake package files)
# and what the tests load at run time, by `dpkg -S`, and on a debootstrap'd Debian 12.
packages=(
  # build
  build-essential cmake pkg-config
  # OpenCL: ICD loader, headers, C++ bindings, PoCL as the CPU device, clinfo to check a driver loads
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  # front ends: model loading, image files, command line, JSON, matrices. zlib1g-dev: assimp's CMake
  # targets link /usr/lib/x86_64-linux-gnu/libz.so, but libassimp-dev does not depend on it.
  libassimp-dev zlib1g-dev libstb-dev libcli11-dev nlohmann-json3-dev libglm-dev
  # the test oracle, Mesa's OpenGL headless through EGL: headers (libgl-dev: GL/glcorearb.h), the
  # libraries find_package(OpenGL COMPONENTS OpenGL EGL) wants (libOpenGL.so: libopengl-dev), and
  # Mesa's EGL and llvmpipe behind them
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  # tests: GoogleTest, Oclgrind for the kernel checks, assimp's test models
  libgtest-dev oclgrind assimp-testmodels
  # the virtual environments Intel's runtime and the Python package are installed into, and the
  # headers the package's extension module is compiled against
  python3-venv python3-dev
  # scripts/fuzz.sh: clang with libFuzzer and the sanitizers' runtimes
  clang-15
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

[ "$mode" = packages ] && exit 0

# ---- 2. Intel's CPU OpenCL runtime ----
# Exact versions, the dependencies' included, so that every machine tests against the same runtime.
intel_packages=(intel-opencl-rt==2026.2.0 intel-cmplr-lib-rt==2026.2.0 intel-cmplr-lic-rt==2026.2.0
                tbb==2023.2.0 tcmlib==1.6.0)
dir=${CLRASTER_INTEL_OPENCL_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/clraster/intel-opencl}
venv=$dir/venv
library=$venv/lib/libintelocl.so
# Written after a complete install: without it (an interrupted install) or with other versions
# in it, the environment is made again.
stamp=$venv/clraster-installed.txt

if [ ! -f "$library" ] || [ "$(cat "$stamp" 2>/dev/null)" != "${intel_packages[*]}" ]; then
  [ "$(uname -m)" = x86_64 ] || { echo "setup: Intel's CPU OpenCL runtime exists for x86-64 only, not $(uname -m)"; exit 1; }
  echo "setup: installing Intel's CPU OpenCL runtime (${intel_packages[0]}, about 700 MB) into $venv"
  rm -rf "$venv"
  mkdir -p "$dir"
  # Debian's Python, which python3-venv belongs to, whatever python3 comes first in PATH.
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --disable-pip-version-check --no-cache-dir "${intel_packages[@]}" || {
    echo "setup: pip could not install Intel's OpenCL runtime (it needs https access to pypi.org)"
    exit 1
  }
  [ -f "$library" ] || { echo "setup: the Intel packages installed, but $library is not there"; exit 1; }
  echo "${intel_packages[*]}" >"$stamp"
fi

# The loader reads one vendors directory: Intel's runtime and copies of the system's drivers (PoCL),
# refreshed each time so that drivers installed or removed since show up.
vendors=$dir/vendors
mkdir -p "$vendors"
icd=$vendors/intel-cpu.icd
[ "$(cat "$icd" 2>/dev/null)" = "$library" ] || echo "$library" >"$icd"
for f in "$vendors"/*.icd; do
  if [ "$f" != "$icd" ] && [ ! -e "/etc/OpenCL/vendors/$(basename "$f")" ]; then rm -f "$f"; fi
done
for f in /etc/OpenCL/vendors/*.icd; do
  if [ -e "$f" ] && ! cmp -s "$f" "$vendors/$(basename "$f")"; then cp "$f" "$vendors/"; fi
done

# The runtime must load: a broken install fails here rather than as a device missing from the tests.
if ! OCL_ICD_VENDORS=$vendors clinfo -l 2>/dev/null | grep -q "Intel(R) OpenCL"; then
  echo "setup: Intel's OpenCL runtime in $venv does not load (OCL_ICD_VENDORS=$vendors clinfo -l):"
  OCL_ICD_VENDORS=$vendors clinfo -l || true
  echo "setup: remove $venv to install it again"
  exit 1
fi

[ "$mode" = env ] && printf 'export OCL_ICD_VENDORS=%q\n' "$vendors" >&3
exit 0
