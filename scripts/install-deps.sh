#!/usr/bin/env bash
# Installs the Debian packages Parallax builds and tests with (the dependency table of
# shared/DESIGN.md). Only missing packages are installed; `apt-get update` runs once, and only when
# something is missing. Works as root, or through sudo otherwise. Non-interactive (CI has no stdin).
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake pkg-config
  # core, io, command line
  libtbb-dev libfast-float-dev libcli11-dev nlohmann-json3-dev
  # tests, benchmarks
  libgtest-dev libbenchmark-dev
  # fuzzing and sanitizers (libFuzzer, ASan, UBSan runtimes)
  clang libclang-rt-14-dev
  # renderer and viewer: window, GL loading, headless EGL, math, panels, images, window tests
  libglfw3-dev libepoxy-dev libegl-dev libgl1-mesa-dri libglm-dev libimgui-dev libstb-dev
  xvfb xdotool
)

missing=()
for package in "${packages[@]}"; do
  # dpkg-query prints "install ok installed" only for a fully installed package.
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$package")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "install-deps: missing packages: ${missing[*]}" >&2
  echo "install-deps: not root and no sudo; install them as root" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
  apt-get install -y -q --no-install-recommends "${missing[@]}" </dev/null
