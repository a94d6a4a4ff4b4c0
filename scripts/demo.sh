#!/usr/bin/env bash
# The README's main command: installs dependencies, builds, and runs the main job on the
# bundled data — for now the exact roundness evaluation of a measured ring-gauge profile
# (171 mm, scanning, 3600 points) with all four ISO 12181-2 reference circles, unfiltered
# and after the ISO 16610-21 Gaussian filter at 50 UPR.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VCMM_BUILD_DIR:-$root/build}"
"$root/scripts/build.sh"
vcmm="$build/cli/vcmm"
profile="$root/examples/profiles/ring_171mm_scan.csv"
"$vcmm" roundness "$profile"
echo
"$vcmm" roundness "$profile" --filter-upr 50
echo
"$vcmm" roundness "$root/examples/profiles/ring_171mm_touch16.csv"
