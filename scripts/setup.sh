#!/usr/bin/env bash
# Installs everything clraster needs to build, run and test on Debian 12, non-interactively.
# Idempotent: packages already present are left alone, so the demo and test commands can call it every time.
set -euo pipefail

packages=(
  # build
  build-essential cmake pkg-config
  # OpenCL: ICD loader, headers, C++ bindings, and PoCL as the CPU device
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  # front ends: model loading, image files, command line, JSON, matrices
  libassimp-dev libstb-dev libcli11-dev nlohmann-json3-dev libglm-dev
  # the test oracle (Mesa's OpenGL, headless through EGL) and kernel checking
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libgtest-dev oclgrind
  # test data
  assimp-testmodels
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
