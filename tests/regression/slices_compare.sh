#!/usr/bin/env bash
# slices_compare.sh STORMLIGHT SCENE.json WORKDIR THRESHOLD [render options...]
# Renders SCENE at its own slices and at 1024 and compares them by relative RMSE on linear HDR:
# the slicing's own error, which more slices converge away (docs/ACCURACY.md, "Slices").
set -euo pipefail
sl=$1 scene=$2 work=$3 threshold=$4
shift 4
mkdir -p "$work"
"$sl" render --scene "$scene" --out "$work/own.exr" --cpu-composite --float --quiet "$@"
"$sl" render --scene "$scene" --out "$work/fine.exr" --cpu-composite --float --quiet --slices 1024 "$@"
"$sl" compare "$work/own.exr" "$work/fine.exr" --threshold "$threshold"
