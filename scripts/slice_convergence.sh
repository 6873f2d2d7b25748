#!/bin/bash
# Each bundled scene at its default slices against the same code at 2048 slices: relative RMSE on
# linear HDR (docs/ACCURACY.md, "Slices"). About a minute on 2 cores.
#
#   scripts/slice_convergence.sh [WORKDIR]
set -euo pipefail
cd "$(dirname "$0")/.."
S=${STORMLIGHT:-build/release/app/stormlight}
work=${1:-$(mktemp -d)}
mkdir -p "$work"
run() {
  local name=$1
  shift
  xvfb-run -a "$S" render "$@" --quiet --float --cpu-composite --out "$work/$name.exr"
  xvfb-run -a "$S" render "$@" --slices 2048 --quiet --float --cpu-composite --out "$work/$name.2048.exr"
  printf '%-16s %s\n' "$name" "$("$S" compare "$work/$name.exr" "$work/$name.2048.exr" --threshold 1 | awk '{print $3}')"
}
run default datasets/cumulonimbus.nc
run katrina ../shared/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc
run sunrise datasets/cumulonimbus.nc --sun-azimuth 90 --sun-elevation 2 --view-azimuth 180 --view-elevation 4
run reg128 datasets/cumulonimbus.nc --width 128 --height 128 --slices 128
for s in fig5_rainbow fig4_glory fig11_dawn fig9_storm_sky fig6_halo fig13_low_albedo supercell; do
  run "$s" --scene "datasets/scenes/$s.json"
done
