#!/usr/bin/env bash
# One prepared run of the renderer's benchmarks on an NVIDIA GPU machine that has the NVIDIA
# driver but none of Parallax's Debian libraries and no network. Two halves:
#
#   scripts/gpu-bench.sh pack
#     Here, on the build machine (Debian), after a Release build of build/apps/parallax/parallax.
#     Builds nothing. Copies the executable (stripped) into gpu-kit/bin/ and every shared library
#     it needs that is neither glibc's nor the NVIDIA driver's into gpu-kit/lib/, each taken from
#     its Debian package (apt-get download + dpkg-deb -x: Debian's versions, not whatever a
#     developer has in /usr/local), with glvnd's libEGL.so.1, libOpenGL.so.0, libGL.so.1,
#     libGLX.so.0 and libGLdispatch.so.0 (libepoxy opens them at run time; the driver supplies
#     the vendor libraries behind them). Never Mesa: a Mesa package among the needs is an error.
#     gpu-kit/ is ignored by git (.gitignore) and must stay under 60 MiB: the device tool carries
#     at most 64 MiB. Prints its size.
#
#   scripts/gpu-bench.sh run [--quick] [--allow-llvmpipe]
#     On the GPU machine, from the repository root, with $OUT a folder whose files come back (the
#     device tool's `run` with carry: ["gpu-kit"]; nothing else of the build is needed):
#       run: {"command": "scripts/gpu-bench.sh run", "carry": ["gpu-kit"], "timeout_s": 560}
#     Puts gpu-kit/lib and the driver's folder on LD_LIBRARY_PATH, points glvnd at the driver's
#     EGL vendor file, checks that EGL gives an NVIDIA renderer (prints GL_RENDERER; llvmpipe or
#     anything else fails, unless --allow-llvmpipe), then, within 8 minutes in all, each step
#     under its own `timeout` (cut to the time left):
#       parallax --version; a 2 M-point demo cloud (`generate`, as scripts/demo.sh makes it) and a
#       100 M-point cloud converted to a Potree octree, both under $TMPDIR (default /tmp), never
#       $OUT; then `bench render` on random points (compute, 64-bit atomics) and orbits of the
#       demo cloud at 1280x720: compute with 64-bit atomics, compute with --no-atomic64, GL_POINTS,
#       `--stereo sbs`, and the viewer's default look (--look viewer, --rasterizer auto; again with
#       --no-atomic64); then
#       the 100 M-point octree orbited with --look viewer, a 3 M budget, at 1920x1080.
#     --quick: the same steps at a small scale (200 k and 2 M points, 320x240, short orbits):
#     what was tested on llvmpipe with the kit's libraries (`run --quick --allow-llvmpipe` here).
#     Results, written as each step ends so that a timeout keeps what was done (the device tool
#     brings back at most 8 files, so steps share files):
#       $OUT/results.jsonl   one line a step: {"step", "exit", "seconds", "result": the JSON of
#                            `bench render --json`, or null}
#       $OUT/summary.txt     the environment (GL_RENDERER, --version, nvidia-smi) and one line a step
#       $OUT/log.txt         every step's stderr
#     Exits 0 when every step succeeded, 1 otherwise; 2 when the kit or the renderer is wrong.
set -uo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
kit=$repo/gpu-kit
binary=$repo/build/apps/parallax/parallax
# glvnd's dispatch libraries (Debian packages), opened by libepoxy with dlopen: ldd does not list
# them. The vendor libraries behind them (libEGL_nvidia, libGLX_nvidia) are the driver's.
glvnd_packages=(libegl1 libopengl0 libgl1 libglx0 libglvnd0)
glvnd_libraries=(libEGL.so.1 libOpenGL.so.0 libGL.so.1 libGLX.so.0 libGLdispatch.so.0)
kit_limit_mib=60

die() {
  echo "gpu-bench: $*" >&2
  exit 2
}

# ---------------------------------------------------------------------------------------------
# pack

# The Debian package that holds library file $1 (its path as ldd prints it or its real path).
package_of() {
  local path=$1 real owner
  real=$(readlink -f "$path")
  for candidate in "$path" "$real" "/usr$path" "${path#/usr}" "/usr$real" "${real#/usr}"; do
    owner=$(dpkg -S "$candidate" 2>/dev/null | head -n1 | cut -d: -f1) && [ -n "$owner" ] &&
      { echo "$owner"; return 0; }
  done
  return 1
}

# The libraries (paths) that ldd resolves for file $1, with LD_LIBRARY_PATH=$2.
needed_libraries() {
  LD_LIBRARY_PATH=${2:-} ldd "$1" | awk '/=> \// { print $1 " " $3 }'
}

is_glibc_package() {
  case $1 in libc6 | libc6-dev) return 0 ;; *) return 1 ;; esac
}
is_mesa_package() {
  case $1 in *mesa* | libgbm1 | libglapi*) return 0 ;; *) return 1 ;; esac
}

pack() {
  [ -x "$binary" ] || die "no $binary: build it first (cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build --target parallax)"
  grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$repo/build/CMakeCache.txt" 2>/dev/null ||
    die "build/ is not a Release build (CMAKE_BUILD_TYPE in build/CMakeCache.txt)"
  if ! command -v apt-get >/dev/null || ! command -v dpkg-deb >/dev/null; then
    die "pack needs apt-get and dpkg-deb (a Debian machine)"
  fi
  # (global: the EXIT trap runs after pack returns)
  work=$(mktemp -d "${TMPDIR:-/tmp}/gpu-kit-pack.XXXXXX")
  trap 'rm -rf "$work"' EXIT
  rm -rf "$kit"
  mkdir -p "$kit/bin" "$kit/lib" "$work/debs" "$work/root"
  objcopy --strip-unneeded "$binary" "$kit/bin/parallax" || die "cannot copy $binary"

  declare -A packages=()  # package -> 1, downloaded and unpacked into $work/root
  declare -A seen=()      # soname -> 1, its package found (or glibc's)
  local -a sonames=()     # what to copy from the unpacked packages
  fetch_package() {
    local package=$1
    [ -n "${packages[$package]:-}" ] && return 0
    is_mesa_package "$package" && die "$package is Mesa's: the kit never carries Mesa (the GPU machine's driver draws)"
    (cd "$work/debs" && apt-get download -q "$package" >/dev/null 2>"$work/apt.log") ||
      die "apt-get download $package failed: $(tail -n2 "$work/apt.log")"
    dpkg-deb -x "$work/debs/${package}"_*.deb "$work/root" || die "dpkg-deb -x of $package failed"
    packages[$package]=1
    echo "  $package $(dpkg-deb -f "$work/debs/${package}"_*.deb Version)"
  }
  # Every library a file needs, resolved here, fetched from its package.
  collect() {
    local file=$1 soname path package
    while read -r soname path; do
      # Already in the kit (the glvnd libraries' needs among each other), or already looked up.
      [ -n "${seen[$soname]:-}" ] || [ "$path" = "$kit/lib/$soname" ] && continue
      seen[$soname]=1
      package=$(package_of "$path") || die "$path (needed by $file) belongs to no Debian package"
      is_glibc_package "$package" && continue
      fetch_package "$package"
      sonames+=("$soname")
    done < <(needed_libraries "$file" "$kit/lib")
  }
  echo "gpu-bench pack: packages (Debian's versions):"
  collect "$kit/bin/parallax"
  for package in "${glvnd_packages[@]}"; do fetch_package "$package"; done
  sonames+=("${glvnd_libraries[@]}")
  copy_sonames() {
    local soname found
    for soname in "$@"; do
      [ -e "$kit/lib/$soname" ] && continue
      found=$(find "$work/root" -name "$soname" \( -type f -o -type l \) | head -n1)
      [ -n "$found" ] || die "$soname is in none of the downloaded packages"
      cp -L "$found" "$kit/lib/$soname"
    done
  }
  copy_sonames "${sonames[@]}"
  # The glvnd libraries' own needs (libGLX needs libX11, ...), resolved against the kit.
  for soname in "${glvnd_libraries[@]}"; do collect "$kit/lib/$soname"; done
  copy_sonames "${sonames[@]}"
  # Nothing may be missing when the kit alone (and glibc) is on the path.
  local missing
  missing=$(for f in "$kit/bin/parallax" "$kit/lib"/*; do LD_LIBRARY_PATH=$kit/lib ldd "$f"; done |
    grep 'not found' | sort -u)
  [ -z "$missing" ] || die "still missing: $missing"
  local bytes mib
  bytes=$(du -sb "$kit" | cut -f1)
  mib=$(( (bytes + 1048575) / 1048576 ))
  echo "gpu-bench pack: $kit: $(find "$kit/lib" -type f | wc -l) libraries and the executable, $mib MiB ($bytes bytes)"
  [ "$mib" -le "$kit_limit_mib" ] || die "the kit is $mib MiB, over $kit_limit_mib MiB: it would not travel"
}

# ---------------------------------------------------------------------------------------------
# run

# A line of figures from one `bench render --json` object on stdin (python3: the GPU machine's
# image has it; nothing without it, the JSON stays in results.jsonl).
figures_of() {
  command -v python3 >/dev/null || return 0
  python3 -c '
import json, sys
r = json.load(sys.stdin)
parts = [r.get("rasterizer", "?")]
if r.get("rasterizer") == "compute":
    parts.append("64-bit atomics" if r.get("atomic64") else "32-bit atomics")
    if r.get("large_splats"):
        parts.append("%d large splats" % r["large_splats"])
if "median_ms" in r:
    parts.append("median %.2f ms, p90 %.2f ms, worst %.2f ms" % (r["median_ms"], r["p90_ms"], r["worst_ms"]))
else:
    parts.append("frame %.2f ms, %.1f M points/s" % (r["frame_ms"], r["points_per_second"] / 1e6))
if "ratio" in r:
    parts.append("reference / this %.2f" % r["ratio"])
if "points_drawn" in r:
    parts.append("%.2f M points a frame" % (r["points_drawn"] / 1e6))
print(", ".join(parts))
' 2>/dev/null
}

# The NVIDIA driver's folders (libEGL_nvidia.so.0) and its glvnd EGL vendor file.
find_driver() {
  driver_libs=""
  local dir
  for dir in /usr/local/nvidia/lib64 /usr/local/nvidia/lib /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib; do
    if ls "$dir"/libEGL_nvidia.so.* >/dev/null 2>&1; then driver_libs=$dir; break; fi
  done
  vendor_file=""
  for dir in /usr/local/nvidia/share/glvnd/egl_vendor.d /usr/share/glvnd/egl_vendor.d /etc/glvnd/egl_vendor.d; do
    if [ -f "$dir/10_nvidia.json" ]; then vendor_file=$dir/10_nvidia.json; break; fi
  done
  if [ -z "$vendor_file" ] && [ -n "$driver_libs" ]; then
    # The driver is there without its vendor file: glvnd only needs the library's name.
    vendor_file=$tmp/10_nvidia.json
    printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "libEGL_nvidia.so.0"}}\n' >"$vendor_file"
  fi
}

run() {
  local quick=0 allow_llvmpipe=0
  for arg in "$@"; do
    case $arg in
      --quick) quick=1 ;;
      --allow-llvmpipe) allow_llvmpipe=1 ;;
      *) die "run: unknown option $arg (use --quick, --allow-llvmpipe)" ;;
    esac
  done
  [ -n "${OUT:-}" ] || die "run: set OUT to the folder for the results"
  [ -x "$kit/bin/parallax" ] || die "no $kit/bin/parallax: run 'scripts/gpu-bench.sh pack' on the build machine and carry gpu-kit"
  mkdir -p "$OUT"
  tmp=${TMPDIR:-/tmp}/parallax-gpu-bench
  rm -rf "$tmp"
  mkdir -p "$tmp"
  local parallax=$kit/bin/parallax
  local start=$SECONDS total=480
  results=$OUT/results.jsonl summary=$OUT/summary.txt log=$OUT/log.txt
  : >"$results"
  : >"$summary"
  : >"$log"
  note() { echo "$*" | tee -a "$summary"; }

  find_driver
  export LD_LIBRARY_PATH=$kit/lib${driver_libs:+:$driver_libs}
  [ -n "$vendor_file" ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor_file
  note "gpu-bench run$([ $quick = 1 ] && echo ' --quick') $(date -u +%FT%TZ) on $(uname -n)"
  note "driver libraries: ${driver_libs:-none found}; EGL vendor file: ${vendor_file:-none}"
  command -v nvidia-smi >/dev/null &&
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>&1 | sed 's/^/nvidia-smi: /' | tee -a "$summary"
  local missing
  missing=$(ldd "$parallax" | grep 'not found')
  [ -z "$missing" ] || die "the kit's executable lacks: $missing"
  note "$("$parallax" --version 2>&1 | head -n3 | tr '\n' ' ')"

  # The renderer EGL gives: a tiny throughput run, whose JSON names it.
  local probe gl_renderer
  probe=$(timeout 30 "$parallax" bench render --points 10000 --width 64 --height 64 -n 1 --json 2>>"$log")
  gl_renderer=$(printf '%s' "$probe" | sed -n 's/.*"renderer":"\([^"]*\)".*/\1/p')
  note "GL_RENDERER: ${gl_renderer:-none (EGL failed: see log.txt)}"
  case $gl_renderer in
    *NVIDIA* | *nvidia*) ;;
    *llvmpipe*) [ $allow_llvmpipe = 1 ] || die "EGL gave llvmpipe (Mesa's CPU renderer), not the NVIDIA driver: see log.txt; --allow-llvmpipe to run anyway" ;;
    *) [ $allow_llvmpipe = 1 ] || die "EGL gave no NVIDIA renderer ('$gl_renderer'): see log.txt" ;;
  esac

  # step NAME SECONDS COMMAND...: runs COMMAND under timeout (cut to the time left), appends its
  # JSON (its last stdout line, when it is one) to results.jsonl and a line to summary.txt.
  local failures=0
  step() {
    local name=$1 limit=$2
    shift 2
    local left=$((total - (SECONDS - start) - 5))
    [ "$limit" -gt "$left" ] && limit=$left
    if [ "$limit" -lt 5 ]; then
      note "$(printf '%-24s skipped: no time left' "$name")"
      printf '{"step":"%s","exit":null,"seconds":0,"result":null}\n' "$name" >>"$results"
      failures=$((failures + 1))
      return
    fi
    echo "== $name: $*" >>"$log"
    local t0=$SECONDS out rc json
    out=$(timeout -k 5 "$limit" "$@" 2>>"$log")
    rc=$?
    json=$(printf '%s\n' "$out" | tail -n1)
    case $json in "{"*"}") ;; *) json=null ;; esac
    printf '{"step":"%s","exit":%d,"seconds":%d,"result":%s}\n' "$name" "$rc" $((SECONDS - t0)) "$json" >>"$results"
    local figures=""
    [ "$json" != null ] && figures=$(printf '%s' "$json" | figures_of)
    note "$(printf '%-24s exit %-3s %4ss  %s' "$name" "$rc" $((SECONDS - t0)) "${figures:-(no figures: see log.txt)}")"
    [ "$rc" = 0 ] || failures=$((failures + 1))
  }

  local demo_points=2000000 big_points=100000000 width=1280 height=720 big_width=1920
  local big_height=1080 orbit=120 big_orbit=120 random_points=20000000
  if [ $quick = 1 ]; then
    demo_points=200000 big_points=2000000 width=320 height=240 big_width=320 big_height=240
    orbit=5 big_orbit=5 random_points=200000
  fi
  local demo=$tmp/sample.ply big=$tmp/big.ply octree=$tmp/big_octree
  step version 10 "$parallax" --version
  step generate-demo 30 "$parallax" generate -q -o "$demo" --points "$demo_points"
  local size=(--width "$width" --height "$height")
  step random-compute 30 "$parallax" bench render --points "$random_points" "${size[@]}" --rasterizer compute --json
  step orbit-compute-atomic64 30 "$parallax" bench render "$demo" --rasterizer compute --orbit "$orbit" "${size[@]}" --json
  step orbit-compute-atomic32 30 "$parallax" bench render "$demo" --rasterizer compute --no-atomic64 --orbit "$orbit" "${size[@]}" --json
  step orbit-points 30 "$parallax" bench render "$demo" --rasterizer points --orbit "$orbit" "${size[@]}" --json
  step orbit-stereo-sbs 30 "$parallax" bench render "$demo" --look viewer --stereo sbs --orbit "$orbit" "${size[@]}" --json
  step orbit-viewer-look 30 "$parallax" bench render "$demo" --look viewer --orbit "$orbit" "${size[@]}" --json
  step orbit-viewer-look-atomic32 30 "$parallax" bench render "$demo" --look viewer --no-atomic64 --orbit "$orbit" "${size[@]}" --json
  rm -f "$demo"
  step generate-big 60 "$parallax" generate -q -o "$big" --points "$big_points"
  step convert-big 120 "$parallax" convert -q "$big" -o "$octree"
  rm -f "$big"
  step orbit-octree-viewer-look 60 "$parallax" bench render "$octree" --look viewer --budget 3000000 --orbit "$big_orbit" --width "$big_width" --height "$big_height" --json
  rm -rf "$tmp"
  note "$failures failed steps; $((SECONDS - start)) s in all"
  [ "$failures" = 0 ]
}

case ${1:-} in
  pack) pack ;;
  run)
    shift
    run "$@"
    ;;
  *)
    echo "usage: scripts/gpu-bench.sh pack | run [--quick] [--allow-llvmpipe]" >&2
    exit 2
    ;;
esac
