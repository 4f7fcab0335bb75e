#!/usr/bin/env bash
# ctest driver of the installation checks (cmake/ParallaxPackaging.cmake):
#
#   check_install.sh install BUILD_DIR WORK_DIR VERSION
#       `cmake --install` into WORK_DIR/prefix; the installed parallax prints its version and
#       features, converts a file it generated, and the documents are there.
#   check_install.sh deb BUILD_DIR WORK_DIR VERSION
#       `cpack -G DEB`; dpkg-deb -I names the package, version and dependencies, dpkg-deb -c
#       lists usr/bin/parallax; every shared library the packaged executable needs is owned
#       (dpkg -S) by a package its Depends line names; the extracted executable runs --version.
# WORK_DIR is emptied first. Exits non-zero, saying why, at the first failure.
set -euo pipefail

mode=${1:?mode} build=${2:?build dir} work=${3:?work dir} version=${4:?version}
fail() { echo "FAILED: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work"

# check_version EXECUTABLE: the --version text of this build.
check_version() {
  local out
  out=$("$1" --version) || fail "$1 --version exited with $?"
  [[ $(head -n 1 <<<"$out") == "parallax $version" ]] ||
    fail "$1 --version: first line '$(head -n 1 <<<"$out")', expected 'parallax $version'"
  grep -q '^features:$' <<<"$out" || fail "no 'features:' in: $out"
  grep -q '^  rendering: OpenGL 4.5 core' <<<"$out" || fail "no rendering feature in: $out"
  grep -q '^  viewer: GLFW' <<<"$out" || fail "no viewer feature in: $out"
  grep -q '^build: ' <<<"$out" || fail "no 'build:' line in: $out"
}

case $mode in
  install)
    prefix=$work/prefix
    cmake --install "$build" --prefix "$prefix" >"$work/install.log" ||
      fail "cmake --install: $(cat "$work/install.log")"
    [[ -x $prefix/bin/parallax ]] || fail "no $prefix/bin/parallax"
    check_version "$prefix/bin/parallax"
    # It works from there: no file of the build tree is needed.
    (cd "$work" && "$prefix/bin/parallax" generate -o "$work/g.ply" --points 1000 >/dev/null &&
      "$prefix/bin/parallax" convert "$work/g.ply" -o "$work/g.las" -q &&
      "$prefix/bin/parallax" info "$work/g.las" --json >"$work/info.json") ||
      fail "the installed parallax could not generate, convert and inspect a file"
    grep -q '"points": *1000' "$work/info.json" || fail "info: $(cat "$work/info.json")"
    for doc in README.md ARCHITECTURE.md FORMATS.md STYLE.md; do
      [[ -f $prefix/share/doc/parallax/$doc ]] || fail "no share/doc/parallax/$doc installed"
    done
    # The Python package, where this build has it (python/CMakeLists.txt), imports from there and
    # reads the file the installed executable wrote.
    if [[ -d $build/python/parallax ]]; then
      site=$prefix/lib/python3/dist-packages
      [[ -f $site/parallax/__init__.py && -f $site/parallax/py.typed ]] ||
        fail "no Python package in $site/parallax"
      (cd "$work" && PYTHONPATH=$site /usr/bin/python3 -c \
        "import sys, parallax; sys.exit(0 if len(parallax.read('g.las')) == 1000 else 1)") ||
        fail "the installed Python module could not read $work/g.las"
    fi
    echo "OK: installed into $prefix; $("$prefix/bin/parallax" --version | head -n 1)"
    ;;
  deb)
    command -v dpkg-deb >/dev/null || fail "dpkg-deb not found (Debian package dpkg)"
    (cd "$work" && cpack --config "$build/CPackConfig.cmake" -G DEB -B "$work" >"$work/cpack.log" 2>&1) ||
      fail "cpack: $(cat "$work/cpack.log")"
    deb=$(find "$work" -maxdepth 1 -name "parallax_${version}_*.deb" | head -n 1)
    [[ -n $deb ]] || fail "no parallax_${version}_*.deb in $work: $(cat "$work/cpack.log")"
    info=$(dpkg-deb -I "$deb")
    grep -q '^ Package: parallax$' <<<"$info" || fail "dpkg-deb -I: no 'Package: parallax': $info"
    grep -q "^ Version: $version\$" <<<"$info" || fail "dpkg-deb -I: no 'Version: $version': $info"
    depends=$(sed -n 's/^ Depends: //p' <<<"$info")
    [[ -n $depends ]] || fail "dpkg-deb -I: no Depends line: $info"
    contents=$(dpkg-deb -c "$deb")
    grep -q ' \./usr/bin/parallax$' <<<"$contents" || fail "dpkg-deb -c: no ./usr/bin/parallax"
    dpkg-deb -x "$deb" "$work/root"
    executable=$work/root/usr/bin/parallax
    # Every package named in Depends, without versions, architectures or alternatives' bars.
    declared=" $(sed -E 's/\([^)]*\)//g; s/:any//g; s/[,|]/ /g' <<<"$depends" | tr -s ' ') "
    # Each library the executable needs (its NEEDED entries) belongs to a declared package: the
    # package that ships the file the loader finds for it here (dpkg -S; with /usr merged, the
    # package may list it under /lib or /usr/lib).
    resolved=$(ldd "$executable")
    for name in $(objdump -p "$executable" | awk '$1 == "NEEDED" { print $2 }'); do
      # ldd lists the dynamic loader by its path alone ("/lib64/ld-linux-x86-64.so.2 (0x...)");
      # code built position-independent needs it by name for thread-local variables.
      path=$(awk -v name="$name" '($1 == name && $2 == "=>") { print $3 }
        (substr($1, 1, 1) == "/" && substr($1, length($1) - length(name)) == "/" name) { print $1 }' <<<"$resolved" | head -n 1)
      [[ $path == /* ]] || fail "$name, needed by the packaged parallax, is not found: $resolved"
      owner=
      for candidate in "$path" "/usr$path" "${path#/usr}"; do
        owner=$(dpkg -S "$candidate" 2>/dev/null | head -n 1 | cut -d: -f1 || true)
        [[ -z $owner ]] || break
      done
      [[ -n $owner ]] || fail "no installed package ships $path ($name)"
      [[ $declared == *" $owner "* ]] ||
        fail "$name comes from $owner, which the package does not declare (Depends: $depends)"
    done
    # The libraries opened at run time (cmake/ParallaxPackaging.cmake says why): declared too.
    for package in libegl1 libgl1 libgl1-mesa-dri; do
      [[ $declared == *" $package "* ]] || fail "Depends lacks $package: $depends"
    done
    check_version "$executable"
    echo "OK: $deb"
    echo "$info" | grep -E '^ (Package|Version|Architecture|Depends):'
    ;;
  *)
    fail "unknown mode '$mode'"
    ;;
esac
