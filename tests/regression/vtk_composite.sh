#!/usr/bin/env bash
# vtk_composite.sh STORMLIGHT STORM.nc WORKDIR: the frame composited by the VTK render pass in a
# float framebuffer equals the CPU composite to float rounding. Needs an X display (xvfb-run).
set -euo pipefail
sl=$1 storm=$2 work=$3
mkdir -p "$work"
if [ -z "${DISPLAY:-}" ]; then
  echo "no X display: run the suite under xvfb-run -a"
  exit 1
fi
args=(--width 160 --height 120 --slices 96 --quiet --float)
"$sl" render "$storm" --out "$work/vtk.exr" "${args[@]}"
"$sl" render "$storm" --out "$work/cpu.exr" --cpu-composite "${args[@]}"
"$sl" compare "$work/vtk.exr" "$work/cpu.exr" --threshold 1e-5
