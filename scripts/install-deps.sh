#!/usr/bin/env bash
# Installs the Debian packages Parallax builds and tests with (the dependency table of
# docs/ARCHITECTURE.md). Only missing packages are installed; `apt-get update` runs once, and only
# when something is missing. Works as root, or through sudo otherwise. Non-interactive (CI has no
# stdin).
set -euo pipefail

packages=(
  # toolchain; packaging (cpack -G DEB: dpkg-shlibdeps, file); the formatter CI checks with
  build-essential cmake pkg-config dpkg-dev file clang-format
  # LLD, the faster linker (PARALLAX_LINK_WITH_LLD)
  lld
  # core, io, command line
  libtbb-dev libfast-float-dev libcli11-dev nlohmann-json3-dev
  # PCD's binary_compressed data (LZF)
  liblzf-dev
  # E57's XML section (src/io/e57)
  libxml2-dev
  # tests, benchmarks
  libgtest-dev libbenchmark-dev
  # fuzzing and sanitizers (libFuzzer, ASan, UBSan runtimes)
  clang libclang-rt-14-dev
  # renderer and viewer: window, GL loading, headless EGL, math, panels, images, window tests
  libglfw3-dev libepoxy-dev libegl-dev libgl1-mesa-dri libglm-dev libimgui-dev libstb-dev
  xvfb xdotool
  # VR (src/xr): the Khronos OpenXR loader; in tests, its core validation layer and hello_xr
  # against the project's own test runtime (tests/xr/runtime), on an X server with the dummy
  # video driver (hello_xr's window needs XFree86-VidMode, which Xvfb lacks)
  libopenxr-dev libopenxr-loader1 openxr-layer-corevalidation libopenxr-utils libx11-dev
  xserver-xorg-core xserver-xorg-video-dummy
  # the real Potree client test (tests/lod/js) and the LAZ oracles (tests/io/js): Node.js (with
  # npm; see install_npm_packages)
  nodejs
  # HTTP(S) byte ranges (src/net), and its tests: a real web server on loopback, the
  # fault-injecting proxy (Python 3 standard library) and a TLS certificate made by openssl
  libcurl4-openssl-dev nginx python3 openssl
  # PCD's oracle in tests (tests/io/test_pcd_pcl.cpp): PCL's own converters
  pcl-tools
  # the distributed conversion's driver (python/parallax_dask) and its tests: Dask distributed
  python3-distributed
  # the Python module (python/parallax: pybind11, numpy) and its tests (pytest)
  pybind11-dev python3-dev python3-numpy python3-pytest
  # the ground's 2D Delaunay triangulation (src/terrain, --height-above-ground; header only)
  libcgal-dev
  # registration's oracle in tests (tests/registration/compare_open3d.py): Open3D's
  # registration_icp, never used by the product
  python3-open3d
  # rasters (src/raster): GeoTIFF through GDAL; gdal_grid, gdalinfo, gdaldem as test oracles
  libgdal-dev gdal-bin
  # rasters' second oracle in tests (tests/raster/compare_cloudcompare.py): CloudCompare's
  # command line -RASTERIZE, never used by the product
  cloudcompare
)

# npm packages of the tests, from their package-lock.json (`npm ci`), only when missing or older
# than the lock file. Debian's nodejs has no npm of its own: its `npm` package is added then.
install_npm_packages() {
  local root dir
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  # tests/lod/js: the Potree client; tests/io/js: laz-perf and copc.js, the LAZ/COPC oracles.
  for dir in "$root/tests/lod/js" "$root/tests/io/js"; do
    if [[ -f "$dir/node_modules/.package-lock.json" &&
          "$dir/node_modules/.package-lock.json" -nt "$dir/package-lock.json" ]]; then
      continue
    fi
    if ! command -v npm >/dev/null 2>&1; then
      "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y -q --no-install-recommends npm </dev/null
    fi
    echo "install-deps: npm ci in $dir"
    (cd "$dir" && npm ci --no-audit --no-fund)
  done
}

missing=()
for package in "${packages[@]}"; do
  # dpkg-query prints "install ok installed" only for a fully installed package.
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$package")
  fi
done

as_root=()
[[ $(id -u) -eq 0 ]] || as_root=(sudo)
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  install_npm_packages
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
install_npm_packages
