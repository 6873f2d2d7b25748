#!/usr/bin/env bash
# map_switches.sh STORMLIGHT WORKDIR: each layer of the scene around the storm is switched on and
# off by its scene key (and flag): on, the frame differs from the bare one; off (false), it is the
# bare frame. Needs an X display (xvfb-run) and GMT's coastline data.
set -euo pipefail
sl=$1 work=$2
mkdir -p "$work"
if [ -z "${DISPLAY:-}" ]; then
  echo "no X display: run the suite under xvfb-run -a"
  exit 1
fi
"$sl" synth cumulonimbus --out "$work/delta.nc" --nx 24 --ny 24 --nz 12 --dx 8000 --center 25.9,-97.4 > /dev/null
args=(--width 96 --height 72 --slices 64 --light-resolution 64 --quiet --float --view-elevation 35)
render() { "$sl" render "$work/delta.nc" --out "$1" "${args[@]}" "${@:2}"; }
render "$work/bare.exr"
for key in terrain coastlines borders graticule domain-outline scale-bar; do
  printf '{"%s": true}\n' "$key" > "$work/on.json"
  printf '{"%s": false}\n' "$key" > "$work/off.json"
  render "$work/$key-on.exr" --scene "$work/on.json"
  render "$work/$key-off.exr" --scene "$work/off.json"
  render "$work/$key-flag.exr" "--$key"
  "$sl" compare "$work/$key-off.exr" "$work/bare.exr" --threshold 0 > /dev/null || { echo "$key: false still changes the frame"; exit 1; }
  "$sl" compare "$work/$key-flag.exr" "$work/$key-on.exr" --threshold 0 > /dev/null || { echo "$key: flag and scene key differ"; exit 1; }
  if "$sl" compare "$work/$key-on.exr" "$work/bare.exr" --threshold 1e-4 > /dev/null; then
    echo "$key: true does not change the frame"
    exit 1
  fi
  echo "$key: on changes the frame, off leaves it"
done
