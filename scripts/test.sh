#!/usr/bin/env bash
# Builds and tests everything CI checks: the formatting of every C++ file, then two trees:
#   1. build/       Release: the product, the Python module and the benchmarks, and the tests
#                   the sanitizer tree cannot run (label `unsanitized`: the Python module, the
#                   Debian package); with --quick, every test instead (and nothing else runs)
#   2. build-asan/  clang, RelWithDebInfo with AddressSanitizer + UndefinedBehaviorSanitizer:
#                   everything else, every other test (LeakSanitizer too; system GL/X11
#                   libraries' leaks: scripts/lsan.supp); and the libFuzzer targets, built in
#                   this tree (the modules they read carry libFuzzer's coverage instrumentation,
#                   fuzz/CMakeLists.txt): after the tests each runs for a fixed time from a copy
#                   of its seed corpus fuzz/corpus/<format>/ and the real files
#                   fuzz/CMakeLists.txt lists from PARALLAX_TEST_DATA (with fuzz/<format>.dict
#                   when present), as many at a time as there are build jobs
# Every tree is built with PARALLAX_WERROR=ON (a compiler warning fails the build) and its build
# log is searched for any other warning (CMake, linker), which fails the stage too.
# Every tree compiles in unity batches (PARALLAX_UNITY_BUILD) and links with LLD where it is
# installed: CI's time is mostly compiling and linking. Every file is compiled by clang (tree 2)
# and the product's also by GCC (tree 1), each with its warnings as errors.
# A skipped test is not a passed one: every skip is listed in the summary with its reason, and a
# skip fails the run unless its test's name matches a pattern of PARALLAX_ALLOWED_SKIPS (empty in
# CI, where Xvfb, xdotool and Mesa are installed and nothing has a reason to skip).
# Every stage runs even when an earlier one failed (so one run shows all problems); the script
# exits non-zero when any stage failed and ends with a summary and a
# "N passed, N failed, N skipped" line.
#
#   scripts/test.sh            everything (about 35 minutes on 2 cores from scratch)
#   scripts/test.sh --quick    the Release tree with every test, nothing else
# Environment: PARALLAX_JOBS (build and test parallelism, default: nproc),
#              PARALLAX_FUZZ_SECONDS (per fuzz target, default 15),
#              PARALLAX_BUILD_DIR (default build; the sanitizer tree is its name + -asan),
#              PARALLAX_TEST_DATA (the folder of other projects' test files, default ../shared/data
#                beside the repository; read by CMake, cmake/ParallaxTestData.cmake),
#              PARALLAX_ALLOWED_SKIPS (test names or shell patterns, separated by blanks, that may
#                skip on this machine, e.g. 'ViewerWindow.*' where there is no Xvfb; default none).
set -uo pipefail

cd "$(dirname "$0")/.." || exit 2
root=$(pwd)
quick=0
for arg in "$@"; do
  case "$arg" in
    --quick) quick=1 ;;
    -h|--help) sed -n '2,/^set/p' "$0" | sed '$d'; exit 0 ;;
    *) echo "test.sh: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
  esac
done

jobs=${PARALLAX_JOBS:-$(nproc)}
fuzz_seconds=${PARALLAX_FUZZ_SECONDS:-15}
release_dir=${PARALLAX_BUILD_DIR:-build}
asan_dir=$release_dir-asan
# The fuzz targets are built and run in the sanitizer tree.
fuzz_dir=$asan_dir
read -r -a allowed_skips <<<"${PARALLAX_ALLOWED_SKIPS:-}"
export DEBIAN_FRONTEND=noninteractive
# Sanitizers: stop at the first report, with a stack; leaks are errors.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/scripts/lsan.supp:print_suppressions=0}
# Golden images are compared, never rewritten, in a test run (scripts/regenerate-golden.sh
# rewrites them, on its own).
unset PARALLAX_REGENERATE_GOLDEN

logs=$(mktemp -d "${TMPDIR:-/tmp}/parallax-test.XXXXXX")
summary=()
failure_lines=()
failed_stages=0
tests_passed=0
tests_failed=0
tests_skipped=0
unexpected_skips=0
skip_lines=()

now() { date +%s; }
banner() { printf '\n==== %s ====\n' "$*"; }

# record NAME STATUS SECONDS
record() {
  summary+=("$(printf '%-34s %-6s %5ss' "$1" "$2" "$3")")
  [[ "$2" == ok ]] || failed_stages=$((failed_stages + 1))
}

# configure_and_build NAME DIR "TARGETS..." -- CMAKE_ARGS...
configure_and_build() {
  local name=$1 dir=$2 targets log="$logs/build-$1.log"
  read -r -a targets <<<"$3"
  shift 4
  banner "$name: configure and build ($dir: ${targets[*]})"
  local start rc warnings
  start=$(now)
  { cmake -S "$root" -B "$dir" -DPARALLAX_WERROR=ON -DPARALLAX_UNITY_BUILD=ON "$@" &&
    cmake --build "$dir" -j "$jobs" --target "${targets[@]}"; } 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  # -Werror stops on a compiler warning; this catches the rest (CMake's, the linker's).
  warnings=$(grep -Eic '(^|[^a-z])warning([: ]|$)' "$log")
  if [[ $warnings -gt 0 ]]; then
    echo "---- $name: $warnings warning line(s) in the build log ($log):"
    grep -Ei '(^|[^a-z])warning([: ]|$)' "$log" | head -n 20
  fi
  local status=ok
  [[ $rc -eq 0 ]] || status=FAILED
  [[ $warnings -eq 0 ]] || status=WARNED
  record "$name build" "$status" $(($(now) - start))
  return "$rc"
}

# skip_allowed NAME: whether NAME matches a pattern of PARALLAX_ALLOWED_SKIPS.
skip_allowed() {
  local pattern
  for pattern in "${allowed_skips[@]}"; do
    # shellcheck disable=SC2053  # the pattern is a glob on purpose
    [[ "$1" == $pattern ]] && return 0
  done
  return 1
}

# count_skips NAME JUNIT: lists every test of the JUnit file that did not run, with the reason
# GoogleTest printed after "Skipped" (or ctest's own); returns 1 if one of them was unexpected.
count_skips() {
  local name=$1 junit=$2 test reason unexpected=0
  [[ -f "$junit" ]] || return 0
  while IFS=$'\t' read -r test reason; do
    [[ -n "$test" ]] || continue
    tests_skipped=$((tests_skipped + 1))
    if skip_allowed "$test"; then
      skip_lines+=("$(printf '  %-6s %s: %s (allowed: PARALLAX_ALLOWED_SKIPS)' "$name" "$test" "$reason")")
    else
      unexpected=$((unexpected + 1))
      skip_lines+=("$(printf '  %-6s %s: %s (UNEXPECTED)' "$name" "$test" "$reason")")
    fi
  done < <(awk '
    /<testcase / && /status="(notrun|disabled)"/ {
      match($0, /name="[^"]*"/); test = substr($0, RSTART + 6, RLENGTH - 7); reason = ""; inside = 1
      next
    }
    inside && /<skipped message=/ && reason == "" {
      match($0, /message="[^"]*"/); reason = substr($0, RSTART + 9, RLENGTH - 10)
    }
    inside && after_skip { reason = $0; after_skip = 0 }
    inside && /: Skipped$/ { after_skip = 1 }
    inside && /<\/testcase>/ {
      gsub(/&quot;/, "\"", reason); gsub(/&apos;/, "\047", reason); gsub(/&lt;/, "<", reason)
      gsub(/&gt;/, ">", reason); gsub(/&amp;/, "\\&", reason)
      printf "%s\t%s\n", test, reason; inside = 0
    }
  ' "$junit")
  unexpected_skips=$((unexpected_skips + unexpected))
  [[ $unexpected -eq 0 ]]
}

# run_ctest NAME DIR [CTEST_ARGS...]: runs every test (or those CTEST_ARGS select), adds the
# counts to the totals.
run_ctest() {
  local name=$1 dir=$2 start rc log="$logs/ctest-$1.log" junit="$logs/ctest-$1.xml"
  shift 2
  banner "$name: ctest ($dir${*:+ $*})"
  start=$(now)
  ctest --test-dir "$dir" --output-on-failure --no-tests=error -j "$jobs" --timeout 600 \
    --output-junit "$junit" "$@" 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  # "100% tests passed, 0 tests failed out of 42"
  # ctest counts a skipped test as passed; the skips are taken back out of that count.
  local line total failed skipped_before=$tests_skipped status=ok
  line=$(grep -E '^[0-9]+% tests passed, [0-9]+ tests? failed out of [0-9]+' "$log" | tail -n 1)
  count_skips "$name" "$junit" || status=SKIPPED
  # Without the JUnit file the skips cannot be counted (a skip would pass as a pass): a failure.
  if [[ ! -s "$junit" ]]; then
    echo "---- $name: ctest wrote no JUnit file ($junit): skips cannot be told from passes"
    status=FAILED
    tests_failed=$((tests_failed + 1))
  fi
  local skipped=$((tests_skipped - skipped_before))
  if [[ -n "$line" ]]; then
    failed=$(sed -E 's/.* ([0-9]+) tests? failed.*/\1/' <<<"$line")
    total=$(sed -E 's/.* out of ([0-9]+).*/\1/' <<<"$line")
    tests_passed=$((tests_passed + total - failed - skipped))
    tests_failed=$((tests_failed + failed))
  elif [[ $rc -ne 0 ]]; then
    tests_failed=$((tests_failed + 1))
  fi
  if [[ $rc -ne 0 ]]; then
    status=FAILED
    # The failed tests' names and their assertion messages, repeated at the end of the run: a
    # CI log that keeps only its tail still says what failed.
    failure_lines+=("$name: $(grep -A 1000 'The following tests FAILED' "$log" | tail -n +2 |
      grep -E '^[[:space:]]+[0-9]+ - ' | sed -E 's/^[[:space:]]+//' | paste -sd ';' -)")
    mapfile -t -O "${#failure_lines[@]}" failure_lines < <(grep -E -A 4 ': Failure$' "$log" | head -n 60)
  fi
  record "$name ctest${line:+ (${total:-?} tests: $((${total:-0} - ${failed:-0} - skipped)) passed, ${failed:-?} failed, $skipped skipped)}" \
    "$status" $(($(now) - start))
}

# prepare_fuzz_corpus EXECUTABLE: a fresh copy of the fuzz target's seeds (the seeds stay
# unchanged); prints the folder, or the problems and returns 1.
prepare_fuzz_corpus() {
  local executable=$1 kind corpus
  kind=$(fuzz_kind "$executable")
  corpus=$(mktemp -d "$logs/corpus-$kind.XXXXXX")
  # A fuzzer started from an empty corpus finds next to nothing in 15 s, and says nothing about
  # it: a missing seed folder, or a real seed file missing from PARALLAX_TEST_DATA, fails the run.
  local problems=() seed_kind seed
  if [[ -d "$root/fuzz/corpus/$kind" && -n "$(ls -A "$root/fuzz/corpus/$kind")" ]]; then
    cp -r "$root/fuzz/corpus/$kind/." "$corpus/"
  else
    problems+=("no seeds in fuzz/corpus/$kind/: add inputs Parallax made (see fuzz/CMakeLists.txt)")
  fi
  while IFS=$'\t' read -r seed_kind seed; do
    [[ "$seed_kind" == "$kind" ]] || continue
    if [[ -f "$seed" ]]; then
      cp "$seed" "$corpus/"
    else
      problems+=("seed $seed not found: set PARALLAX_TEST_DATA to the folder of other projects' test files (in CI ../shared/data beside the clone) and reconfigure $fuzz_dir")
    fi
  done <"$fuzz_dir/fuzz/fuzz_test_data_seeds.txt"
  if [[ ${#problems[@]} -gt 0 ]]; then
    printf '%s\n' "${problems[@]}"
    return 1
  fi
  echo "$corpus"
}

# fuzz_kind EXECUTABLE: fuzz_las_reader -> las (the name of its corpus folder and dictionary).
fuzz_kind() {
  local name kind
  name=$(basename "$1")
  kind=${name#fuzz_}
  echo "${kind%_reader}"
}

# run_fuzzers EXECUTABLE...: each for a fixed time from a copy of its seed corpus, $jobs at a time
# (each fuzzer uses one core), then each one's result in the order given.
run_fuzzers() {
  local executable name kind corpus names=() starts=() problems
  mkdir -p "$root/$fuzz_dir/artifacts"
  for executable in "$@"; do
    name=$(basename "$executable")
    kind=$(fuzz_kind "$executable")
    if ! problems=$(prepare_fuzz_corpus "$executable"); then
      while IFS= read -r line; do printf -- '---- %s FAILED: %s\n' "$name" "$line"; done <<<"$problems"
      tests_failed=$((tests_failed + 1))
      record "fuzz $name" FAILED 0
      continue
    fi
    corpus=$problems
    local extra=()
    [[ -f "$root/fuzz/$kind.dict" ]] && extra+=("-dict=$root/fuzz/$kind.dict")
    while [[ $(jobs -rp | wc -l) -ge $jobs ]]; do wait -n; done
    banner "fuzz: $name for ${fuzz_seconds}s (log: $logs/$name.log)"
    names+=("$name")
    starts+=("$(now)")
    (
      "$executable" -max_total_time="$fuzz_seconds" -rss_limit_mb=2048 -timeout=10 \
        -print_final_stats=1 -artifact_prefix="$root/$fuzz_dir/artifacts/$name-" "${extra[@]}" \
        "$corpus" >"$logs/$name.log" 2>&1 </dev/null
      echo $? >"$logs/$name.rc"
      now >"$logs/$name.end"
    ) &
  done
  wait
  local i rc
  for i in "${!names[@]}"; do
    name=${names[$i]}
    rc=$(cat "$logs/$name.rc" 2>/dev/null || echo 255)
    echo "---- $name:"
    grep -E '^stat::(number_of_executed_units|new_units_added|peak_rss_mb)' "$logs/$name.log" || true
    if [[ $rc -eq 0 ]]; then
      tests_passed=$((tests_passed + 1))
    else
      tests_failed=$((tests_failed + 1))
      echo "---- $name failed (exit $rc); the end of its log:"
      tail -n 60 "$logs/$name.log"
      echo "---- the input that failed is in $fuzz_dir/artifacts/"
    fi
    record "fuzz $name" "$([[ $rc -eq 0 ]] && echo ok || echo FAILED)" \
      $(($(cat "$logs/$name.end" 2>/dev/null || now) - ${starts[$i]}))
  done
}

total_start=$(now)
# The sanitizer tree (tests and fuzz targets): -O1 (ASan's own advice for usable speed, and what
# OSS-Fuzz builds its fuzzers with): its build is a large part of CI's time, and -O2 adds to it
# more than it gives back in test time or executions a second; line tables only (-g1) instead of
# full debug information, which is all a sanitizer's stack trace reads.
sanitizer_flags=(-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG")

banner "dependencies"
start=$(now)
if scripts/install-deps.sh </dev/null; then
  record "install-deps" ok $(($(now) - start))
else
  record "install-deps" FAILED $(($(now) - start))
fi

# 0. Formatting: every C++ file as the root .clang-format has it (clang-format 14, Debian 12's).
banner "format: clang-format --dry-run -Werror"
start=$(now)
if git -C "$root" ls-files -z '*.h' '*.cpp' '*.cc' | xargs -0 -r clang-format --dry-run -Werror; then
  record "format" ok $(($(now) - start))
else
  record "format" FAILED $(($(now) - start))
fi

# 1. Release. With --quick: everything, every test. In the full run every test runs once, under
#    the sanitizers (stage 2): this tree builds what a user builds (the product, the Python
#    module, the benchmarks: they keep compiling, at -O3, warnings included) and runs only the
#    tests the sanitizer tree cannot (ctest label `unsanitized`: the Python module's, the Debian
#    package's). Running every test in both trees cost CI a Release build of every test and a
#    second pass of the suite.
#    The install target does not depend on `all` (CMAKE_SKIP_INSTALL_ALL_DEPENDENCY), so that the
#    package test installs what was built instead of building the tests first.
release_args=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_SKIP_INSTALL_ALL_DEPENDENCY=ON)
if [[ $quick -eq 1 ]]; then
  if configure_and_build release "$release_dir" all -- "${release_args[@]}"; then
    run_ctest release "$release_dir"
  fi
elif configure_and_build release "$release_dir" parallax_product -- "${release_args[@]}"; then
  run_ctest release "$release_dir" -L unsanitized
fi

# use_clang DIR: a tree configured with another compiler cannot be switched in place.
use_clang() {
  if [[ -f "$1/CMakeCache.txt" ]] &&
     ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' "$1/CMakeCache.txt"; then
    rm -rf "$1"
  fi
}

if [[ $quick -eq 0 ]]; then
  # 2. Sanitizers: every test under ASan + UBSan, built by clang; no benchmarks (the Release
  #    tree builds them). Clang, not GCC: with the sanitizers it compiled a unit in 0.55-0.8 of
  #    GCC's CPU time, and this tree is the largest build of the run; so every file goes through
  #    clang (warnings as errors) here and the product's through GCC in the Release tree.
  #    The fuzz targets are built here too (PARALLAX_BUILD_FUZZ; the modules they read get
  #    libFuzzer's coverage instrumentation) and run after the tests: a tree of their own
  #    compiled those modules a third time (264 s of CI).
  use_clang "$asan_dir"
  if configure_and_build asan "$asan_dir" all -- -DCMAKE_BUILD_TYPE=RelWithDebInfo \
       "${sanitizer_flags[@]}" -DCMAKE_CXX_COMPILER=clang++ -DPARALLAX_SANITIZE=ON \
       -DPARALLAX_BUILD_FUZZ=ON -DPARALLAX_BUILD_BENCH=OFF; then
    run_ctest asan "$asan_dir"
    # 3. Fuzzing: each fuzz target for a fixed time.
    fuzzers=()
    while read -r target; do
      [[ -n "$target" ]] && fuzzers+=("$fuzz_dir/fuzz/$target")
    done <"$fuzz_dir/fuzz/fuzz_targets.txt"
    run_fuzzers "${fuzzers[@]}"
  fi
fi

banner "summary ($(($(now) - total_start))s in all; logs in $logs)"
printf '%s\n' "${summary[@]}"
if [[ ${#skip_lines[@]} -gt 0 ]]; then
  echo "skipped tests ($unexpected_skips unexpected; allow one on a machine that lacks what it needs"
  echo "with PARALLAX_ALLOWED_SKIPS='NAME-OR-PATTERN ...'):"
  printf '%s\n' "${skip_lines[@]}"
fi
if [[ ${#failure_lines[@]} -gt 0 ]]; then
  echo "failed tests, and their messages:"
  printf '%s\n' "${failure_lines[@]}"
fi
if [[ $failed_stages -eq 0 ]]; then
  echo "all stages passed"
else
  echo "$failed_stages stage(s) FAILED"
fi
# Tests counted: every ctest test of every tree, and each fuzz target as one.
echo "$tests_passed passed, $tests_failed failed, $tests_skipped skipped ($unexpected_skips unexpected)"
[[ $failed_stages -eq 0 && $tests_failed -eq 0 && $unexpected_skips -eq 0 ]]
