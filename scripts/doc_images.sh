#!/bin/bash
# doc_images.sh [STORMLIGHT] [OUTDIR]: renders the pictures of the README's "real WRF output",
# fog and haze sections and of docs/SCENES.md, SERIES.md and GEOREFERENCING.md from the real WRF
# files in ../shared/data/wrf/ and Stormlight's own synthetic storms, with the commands their
# captions give, and copies them into docs/images/ (readme_images.sh does the hero, the montage and
# the CM1 pictures). Run it after a change that moves pixels. Needs an X display for the VTK
# composite (xvfb-run -a bash scripts/doc_images.sh) and the shared data beside the checkout.
set -euo pipefail
cd "$(dirname "$0")/.."
sl=${1:-build/release/app/stormlight}
out=${2:-/tmp/stormlight_doc_images}
mkdir -p "$out"
wrf=../shared/data/wrf
katrina=$wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc
q=(--quiet)

# Katrina at 18 UTC from an aircraft's height over the sea (albedo 0.06: the file has no land mask),
# alone and with the scene around it (terrain from HGT, water from GSHHG).
view=(--time 2 --view-elevation 25 --fov 30 --width 480 --height 360)
"$sl" render "$katrina" "${view[@]}" "${q[@]}" --ground-albedo 0.06 --out "$out/katrina.png"
"$sl" render "$katrina" "${view[@]}" "${q[@]}" --terrain --graticule --domain-outline --scale-bar \
  --out "$out/katrina_terrain.png"

# Toward a low sun: clear air beside fog, and beside haze (the glow is an image-space step).
for s in fog_clear fog_glow haze_sun; do
  "$sl" render --scene "datasets/scenes/$s.json" --width 480 --height 360 "${q[@]}" --out "$out/$s.png"
done
"$sl" montage "$out/fog_clear.png" "$out/fog_glow.png" --columns 2 --out "$out/fog_glow_pair.png"
"$sl" montage "$out/fog_clear.png" "$out/haze_sun.png" --columns 2 --out "$out/haze_sun_pair.png"

# The Tibetan plateau's own terrain and albedo.
"$sl" render "$wrf/wrf_tibet2005_d01_lambert_thompson_4t_tiny.nc" --time 3 --terrain --domain-outline --scale-bar \
  --view-elevation 15 --width 480 --height 320 "${q[@]}" --out "$out/tibet_terrain.png"

# Map layers on synthetic storms: the Rio Grande's mouth (coast and border), the Pyrenees.
"$sl" synth cumulonimbus --center 25.9,-97.4 --dx 8000 --nx 24 --ny 24 --out "$out/rio_grande.nc" >/dev/null
"$sl" render "$out/rio_grande.nc" --terrain --coastlines --borders --graticule --domain-outline --scale-bar \
  --view-elevation 35 --width 320 --height 240 \
  "${q[@]}" --out "$out/map_layers_coast.png"
"$sl" synth cumulonimbus --center 42.6,0.5 --nx 64 --ny 48 --dx 8000 --out "$out/pyrenees.nc" >/dev/null
"$sl" render "$out/pyrenees.nc" --terrain --coastlines --borders --graticule --sun-elevation 45 --sun-azimuth 180 \
  --camera-position 0,-50000,500000 --camera-target 0,0,0 --fov 50 --width 560 --height 420 "${q[@]}" \
  --out "$out/pyrenees_borders.png"

# Katrina's four times along a camera path by date (docs/SERIES.md).
cat > "$out/fly.json" <<EOF
{
  "data": "$(realpath "$katrina")",
  "ground-albedo": 0.06,
  "camera_keys": [
    {"time": "2005-08-28T12:00:00Z", "position": [-150000, -250000, 60000], "look_at": [0, 0, 4000], "fov": 40},
    {"time": "2005-08-28T21:00:00Z", "position": [150000, -250000, 60000], "look_at": [0, 0, 4000], "fov": 40}
  ]
}
EOF
mkdir -p "$out/fly"
"$sl" render --scene "$out/fly.json" --times all --width 256 --height 160 --light-resolution 256 "${q[@]}" \
  --out "$out/fly/f_%04d.png"
"$sl" montage "$out"/fly/f_000[0-3].png --columns 2 --out "$out/katrina_series.png"

# Katrina from 800 m on the round earth (docs/GEOREFERENCING.md).
"$sl" render "$katrina" --time 2 --origin 22.6,-90.35 --curvature drop --camera-position 0,0,800 \
  --camera-target 0,200000,-2500 --fov 24 --terrain --width 640 --height 320 "${q[@]}" \
  --out "$out/katrina_low_camera_drop.png"

cp "$out/katrina.png" "$out/katrina_terrain.png" "$out/tibet_terrain.png" "$out/map_layers_coast.png" \
  "$out/pyrenees_borders.png" "$out/katrina_series.png" "$out/katrina_low_camera_drop.png" docs/images/
cp "$out/fog_glow_pair.png" docs/images/fog_glow.png
cp "$out/haze_sun_pair.png" docs/images/haze_sun.png
echo "wrote docs/images/katrina.png, katrina_terrain.png, fog_glow.png, haze_sun.png, tibet_terrain.png," \
  "map_layers_coast.png, pyrenees_borders.png, katrina_series.png, katrina_low_camera_drop.png (frames in $out)"
