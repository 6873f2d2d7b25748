#!/usr/bin/env bash
# render_compare.sh STORMLIGHT STORM.nc BASELINE.exr WORKDIR [render options...]
# Renders STORM with the CPU composite and compares it with BASELINE (relative RMSE <= 0.005:
# the baseline is stored in half floats, whose rounding alone gives about 3e-4).
# SL_UPDATE_BASELINES=1 rewrites the baseline instead (review the PNG before committing it).
set -euo pipefail
sl=$1 storm=$2 baseline=$3 work=$4
shift 4
mkdir -p "$work"
"$sl" render "$storm" --out "$work/frame.exr,$work/frame.png" --cpu-composite "$@"
if [ "${SL_UPDATE_BASELINES:-0}" = 1 ]; then
  cp "$work/frame.exr" "$baseline"
  echo "updated $baseline"
  exit 0
fi
"$sl" compare "$work/frame.exr" "$baseline" --threshold 0.005 --diff "$work/diff.png"
