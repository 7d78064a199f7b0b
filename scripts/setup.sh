#!/usr/bin/env bash
# Installs everything clraster needs to build, run and test on Debian 12, non-interactively.
# Idempotent: packages already present are left alone, so the demo and test commands can call it every time.
set -euo pipefail

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
