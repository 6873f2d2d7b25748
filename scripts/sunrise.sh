#!/usr/bin/env bash
# sunrise.sh [STORMLIGHT] [STORM.nc] [OUTDIR]: a sunrise series of a storm, sun elevation from
# -1 to 20 degrees in the east, seen from the south, and a contact strip of the frames.
set -euo pipefail
sl=${1:-build/release/app/stormlight}
storm=${2:-datasets/cumulonimbus.nc}
out=${3:-out/sunrise}
mkdir -p "$out"
frames=()
for el in -1 0 0.5 1 2 3 4 6 8 11 15 20; do
  f="$out/sunrise_${el}.png"
  "$sl" render "$storm" --out "$out/sunrise_${el}.exr,$f" --cpu-composite --quiet \
    --width 240 --height 180 --sun-azimuth 90 --sun-elevation "$el" --view-azimuth 180 --view-elevation 4
  frames+=("$f")
done
"$sl" montage "${frames[@]}" --columns 6 --out "$out/sunrise_strip.png"
echo "wrote ${#frames[@]} frames and $out/sunrise_strip.png"
