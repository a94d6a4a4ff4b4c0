#!/usr/bin/env bash
# Throughput of `vcmm roundness` in batch mode (issue 11): N profile files of 3600 points (a
# 171 mm ring with ~200 nm form and 0.1 µm noise, each file its own noise), evaluated as one
# directory — all four reference circles, certificates verified, one CSV row per file — on
# T threads. Prints files/s (median of R runs). The files are generated once into DIR and kept.
#   benchmarks/roundness_batch.sh [VCMM] [N=10000] [THREADS=2] [RUNS=3] [DIR=/tmp/vcmm_batch_N]
set -euo pipefail
vcmm="${1:-build/cli/vcmm}"
n="${2:-10000}"
threads="${3:-2}"
runs="${4:-3}"
dir="${5:-/tmp/vcmm_batch_$n}"
if [[ ! -f "$dir/.complete" ]]; then
  mkdir -p "$dir"
  python3 - "$dir" "$n" <<'EOF'
import math, random, sys
d, n = sys.argv[1], int(sys.argv[2])
form = [(2, 45e-6, 0.3), (3, 30e-6, 1.1), (4, 12e-6, 2.0), (5, 10e-6, 0.7), (7, 6e-6, 2.9),
        (11, 4e-6, 1.6), (17, 3e-6, 0.2)]
cos_sin = [(math.cos(2 * math.pi * j / 3600), math.sin(2 * math.pi * j / 3600)) for j in range(3600)]
shape = [sum(a * math.cos(k * 2 * math.pi * j / 3600 + p) for k, a, p in form) for j in range(3600)]
for f in range(n):
    rng = random.Random(f)
    lines = []
    for j in range(3600):
        r = 85.5 + shape[j] + rng.gauss(0.0, 1e-4)
        c, s = cos_sin[j]
        lines.append(f"{600 + r * c:.9f},{500 + r * s:.9f}\n")
    with open(f"{d}/p{f:05d}.csv", "w") as out:
        out.writelines(lines)
EOF
  touch "$dir/.complete"
fi
times=()
for ((r = 0; r < runs; ++r)); do
  start=$(date +%s.%N)
  "$vcmm" roundness "$dir" --threads "$threads" -o "$dir/../vcmm_batch_out.csv" || true
  end=$(date +%s.%N)
  times+=("$(awk -v a="$start" -v b="$end" 'BEGIN {print b - a}')")
done
median=$(printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
rate=$(awk -v n="$n" -v t="$median" 'BEGIN {print n / t}')
printf 'vcmm roundness batch: %d files of 3600 points, %d threads: median %.2f s over %d runs = %.0f files/s\n' \
  "$n" "$threads" "$median" "$runs" "$rate"
