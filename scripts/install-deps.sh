#!/usr/bin/env bash
# Installs every Debian 12 package Strata needs to build, test and run. Idempotent: it installs only
# what is missing, and does nothing (not even `apt-get update`) when everything is there.
# Uses sudo when not run as root.
set -euo pipefail

packages=(
  # build
  cmake ninja-build g++-12 pkg-config
  # core libraries
  libpng-dev libstb-dev libtinyexr-dev libglm-dev libeigen3-dev libcli11-dev nlohmann-json3-dev libtbb-dev
  # JPEG decoding: libjpeg-turbo's error manager reports corrupt data and a premature end, which stb_image
  # decodes as grey without a word
  libjpeg62-turbo-dev
  # meshes
  libtinyobjloader-dev libtinygltf-dev
  # generalized displacement maps: Embree 3 ray casting, OpenVDB level sets (its CMake module needs Boost),
  # Spectra (the largest eigenpairs of a large Gram matrix, for the SVD's wide layout). libboost-iostreams-dev
  # also brings Boost's headers (libboost1.74-dev): the environment module uses Boost.Math's Gauss-Legendre rules
  libembree-dev libopenvdb-dev libboost-iostreams-dev libspectra-dev
  # OpenGL 4.5 core through libepoxy, headless through EGL on Mesa (llvmpipe when there is no GPU)
  libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  # the viewer (strata-view): GLFW windows, Dear ImGui with its GLFW / OpenGL 3 backends; its tests run it
  # under xvfb-run (a virtual X display: xvfb, xauth)
  libglfw3-dev libimgui-dev xvfb xauth
  # tests and benchmarks; glslangValidator checks every shader
  libgtest-dev libbenchmark-dev glslang-tools
  # the `fuzz` preset (scripts/fuzz.sh, docs/fuzzing.md): clang with libFuzzer and its sanitizer runtimes
  clang-14 libclang-rt-14-dev
)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages are installed"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: not root and no sudo: install ${missing[*]} by hand" >&2; exit 1; }
  sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
