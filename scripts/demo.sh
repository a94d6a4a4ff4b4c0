#!/usr/bin/env bash
# The README's main command: installs dependencies, builds, and runs the validation demo on
# bundled data (docs/demo.md): a synthetic ground-truth world — the 171 mm ring gauge with
# ~200 nm form, a CMM whose true errors are one draw of examples/cmm_model.json — measured 66
# times as the seed study did (7 locations and 4 ring orientations, 3 heights, scanning and
# touch-trigger; RONt about the maximum-inscribed circle), each evaluated by Monte Carlo
# (10^4 trials), its roundness corrected by the shrinkage treatment and by the seed study's,
# compared with its reference values (E_n); then the figures and the HTML report.
#   ./scripts/demo.sh [OUTDIR] [extra vcmm demo options, e.g. --trials 1000]
# Rerunning resumes: finished measurements are not redone.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VCMM_BUILD_DIR:-$root/build}"
out="${1:-$root/out/demo}"
shift || true
"$root/scripts/build.sh"
"$build/cli/vcmm" demo --model "$root/examples/cmm_model.json" -o "$out" "$@"
# `vcmm report` finds a Python with matplotlib (scripts/install-deps.sh installs Debian's).
"$build/cli/vcmm" report "$out"
echo
echo "report: $out/report.html   tables: $out/results.csv, $out/summary.csv, $out/treatments.csv"
