#!/usr/bin/env bash
# Fuzzes every file reader of vcmm with libFuzzer (docs/fuzzing.md).
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET ...]
#
# Installs what is missing (vcmm's dependencies, clang and its libFuzzer runtime, with
# apt-get), configures and builds the fuzz targets with clang (-DVCMM_FUZZ=ON: libFuzzer,
# ASan, UBSan) in ${VCMM_FUZZ_BUILD_DIR:-build-fuzz}, then runs each target for
# SECONDS_PER_TARGET seconds (default 60), one after the other, and prints a table: seconds,
# executions, executions per second, coverage (cov: edges, ft: features) at the end, corpus
# size, and what went wrong. Targets: all by default (names as in fuzz/CMakeLists.txt).
#
# The working corpus lives in BUILD/corpus/<target>/ and grows across runs. It is seeded from
# fuzz/corpus/<target>/ (small checked-in seeds), the matching files of examples/ and the
# saved regressions tests/data/fuzz_regressions/<target>/. A failing input is saved in
# BUILD/artifacts/<target>/ (crash-*, leak-*, timeout-*, oom-*), minimised next to it
# (minimized-*), and the script exits 1; the logs are in BUILD/logs/<target>.log.
#
# Environment: VCMM_FUZZ_MAX_LEN (bytes, default 8192), VCMM_FUZZ_TIMEOUT (seconds per
# input, default 10), VCMM_FUZZ_RSS_MB (default 2048).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VCMM_FUZZ_BUILD_DIR:-$root/build-fuzz}"
seconds="${1:-60}"
shift || true
max_len="${VCMM_FUZZ_MAX_LEN:-8192}"
timeout="${VCMM_FUZZ_TIMEOUT:-10}"
rss_mb="${VCMM_FUZZ_RSS_MB:-2048}"
all_targets=(points_csv measurement_csv roundness_profile_csv digital_model_json campaign_json
             hole_plate_csv hole_plate_placement_csv)
targets=("$@")
((${#targets[@]})) || targets=("${all_targets[@]}")
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "fuzz.sh: SECONDS_PER_TARGET must be a whole number; got '$seconds'" >&2; exit 2; }
for t in "${targets[@]}"; do
  [[ " ${all_targets[*]} " == *" $t "* ]] || { echo "fuzz.sh: unknown target '$t' (one of: ${all_targets[*]})" >&2; exit 2; }
done

# ---- tools: vcmm's dependencies, clang, libFuzzer -----------------------------------------
"$root/scripts/install-deps.sh"
as_root() { if [[ $(id -u) -eq 0 ]]; then "$@"; else sudo "$@"; fi; }
libfuzzer_links() {  # can clang++ link a libFuzzer target?
  local dir; dir="$(mktemp -d)"
  printf '%s\n' '#include <cstddef>' '#include <cstdint>' \
    'extern "C" int LLVMFuzzerTestOneInput(const uint8_t*, size_t) { return 0; }' >"$dir/t.cpp"
  clang++ -fsanitize=fuzzer,address,undefined "$dir/t.cpp" -o "$dir/t" >/dev/null 2>&1
  local rc=$?; rm -rf "$dir"; return $rc
}
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: installing clang"
  export DEBIAN_FRONTEND=noninteractive
  as_root apt-get update -qq
  as_root apt-get install -y -qq --no-install-recommends clang
fi
if ! libfuzzer_links; then
  # Debian ships the sanitizer and libFuzzer runtimes as libclang-rt-<major>-dev.
  major="$(clang++ --version | sed -n 's/.*clang version \([0-9]*\).*/\1/p' | head -n1)"
  echo "fuzz.sh: installing libclang-rt-$major-dev (libFuzzer runtime)"
  export DEBIAN_FRONTEND=noninteractive
  as_root apt-get update -qq
  as_root apt-get install -y -qq --no-install-recommends "libclang-rt-$major-dev"
  libfuzzer_links || { echo "fuzz.sh: clang++ still cannot link -fsanitize=fuzzer" >&2; exit 1; }
fi

# ---- build ----------------------------------------------------------------------------------
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_COMPILER=clang++ -DVCMM_FUZZ=ON -DVCMM_BUILD_TESTS=OFF \
    -DVCMM_BUILD_BENCHMARKS=OFF -DVCMM_BUILD_CLI=OFF
fi
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/fuzz_}"

# ---- seeds ----------------------------------------------------------------------------------
ex="$root/examples"
seeds_of() {  # the examples/ files that seed target $1
  case "$1" in
    points_csv) echo "$ex"/profiles/*.csv "$ex"/characterization/noise/scan_a.csv \
                     "$ex"/characterization/noise/touch16.csv "$ex"/characterization/sphere/*.csv ;;
    roundness_profile_csv) echo "$ex"/characterization/noise/reference_171mm.csv ;;
    digital_model_json) echo "$ex"/cmm_model.json ;;
    hole_plate_csv) echo "$ex"/characterization/hole_plate/plate.csv ;;
    hole_plate_placement_csv) echo "$ex"/characterization/hole_plate/x[yz]_*.csv \
                                   "$ex"/characterization/hole_plate/yz_*.csv ;;
    *) ;;  # measurement_csv, campaign_json: no example file; checked-in seeds only
  esac
}

# ---- run ------------------------------------------------------------------------------------
summary="$build/fuzz-summary.txt"
printf '%-26s %7s %12s %9s %7s %7s %7s  %s\n' target seconds execs exec/s cov ft corpus \
  result >"$summary"
failed=0
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t" artifacts="$build/artifacts/$t" log="$build/logs/$t.log"
  mkdir -p "$corpus" "$artifacts" "$build/logs"
  for f in $(seeds_of "$t") "$root"/fuzz/corpus/"$t"/* "$root"/tests/data/fuzz_regressions/"$t"/*; do
    [[ -f "$f" ]] && cp -p "$f" "$corpus/seed-$(basename "$f")"
  done
  dict=()
  [[ -f "$root/fuzz/dicts/$t.dict" ]] && dict=(-dict="$root/fuzz/dicts/$t.dict")
  echo "fuzz.sh: $t for ${seconds} s (log $log)"
  start=$(date +%s)
  rc=0
  "$build/fuzz/fuzz_$t" "$corpus" "${dict[@]}" -max_total_time="$seconds" -max_len="$max_len" \
    -timeout="$timeout" -rss_limit_mb="$rss_mb" -artifact_prefix="$artifacts/" \
    -print_final_stats=1 >"$log" 2>&1 || rc=$?
  elapsed=$(( $(date +%s) - start ))
  result="ok"
  if ((rc != 0)); then
    failed=1
    artifact="$(ls -t "$artifacts"/{crash,leak,timeout,oom}-* 2>/dev/null | head -n1 || true)"
    result="FAILED (exit $rc) ${artifact:-see log}"
    if [[ -n "$artifact" ]]; then  # a smaller input that fails the same way, for the test
      "$build/fuzz/fuzz_$t" "$artifact" -minimize_crash=1 -runs=20000 -max_total_time=60 \
        -timeout="$timeout" -exact_artifact_path="$artifacts/minimized-$(basename "$artifact")" \
        >>"$log" 2>&1 || true
    fi
  fi
  # libFuzzer's final statistics and its last status line ("#N DONE cov: C ft: F corp: K/…").
  awk -v t="$t" -v s="$elapsed" -v r="$result" '
    /^stat::number_of_executed_units:/ { execs = $2 }
    /^stat::average_exec_per_sec:/ { rate = $2 }
    /^#[0-9]+/ && / cov: / {
      for (i = 1; i <= NF; ++i) {
        if ($i == "cov:") cov = $(i + 1)
        if ($i == "ft:") ft = $(i + 1)
        if ($i == "corp:") corp = $(i + 1)
      }
      if (execs == "") last = substr($1, 2)
    }
    END {
      if (execs == "") execs = (last == "" ? "?" : last)
      printf "%-26s %7s %12s %9s %7s %7s %7s  %s\n", t, s, execs, (rate == "" ? "?" : rate),
             (cov == "" ? "?" : cov), (ft == "" ? "?" : ft), (corp == "" ? "?" : corp), r
    }' "$log" >>"$summary"
done
echo
cat "$summary"
echo "(cov: edges covered, ft: libFuzzer features, corpus: inputs/bytes; table in $summary)"
exit "$failed"
