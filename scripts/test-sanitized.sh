#!/usr/bin/env bash
# The sanitized suite (issue 12): vcmm, its tests, examples and benchmarks built with
# AddressSanitizer + UndefinedBehaviorSanitizer (-DVCMM_SANITIZE=ON, warnings as errors,
# RelWithDebInfo: -O2 -g) in ${VCMM_SANITIZE_BUILD_DIR:-build-san}, then every test run with
# leak detection on and every finding fatal. Not part of ./scripts/test.sh (too slow for CI).
#
# Any finding fails: ASan and LSan reports (also from the `vcmm` processes the CLI tests
# start, whose stderr the tests capture) go to files in <build>/sanitizer-logs/, and the
# script fails when any file is there, even if the test that caused it passed, and prints
# them. UBSan (GCC 12 ignores log_path for it next to ASan) prints to stderr and aborts: the
# test fails, a CLI test through the exit code (134) it did not expect.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VCMM_SANITIZE_BUILD_DIR:-$root/build-san}"
VCMM_BUILD_DIR="$build" "$root/scripts/build.sh" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DVCMM_SANITIZE=ON -DVCMM_WERROR=ON "$@"

logs="$build/sanitizer-logs"
rm -rf "$logs"
mkdir -p "$logs"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:log_path=$logs/report"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:abort_on_error=1"

cd "$build"
status=0
ctest --output-on-failure -j "$(nproc)" --timeout 3600 || status=$?
if compgen -G "$logs/*" >/dev/null; then
  echo "test-sanitized: sanitizer reports in $logs:" >&2
  cat "$logs"/* >&2
  status=1
fi
exit "$status"
