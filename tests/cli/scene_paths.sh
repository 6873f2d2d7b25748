#!/usr/bin/env bash
# scene_paths.sh STORMLIGHT WORKDIR SHARED: one scene with --curvature drop and --origin drawn by
# `render` and by the path `validate` and `reference` take (sl_settings_from_scene and sl_scene_load, then the fast
# renderer's frame.exr): the frames are the same, bit for bit; and the scene without them is a
# different frame, so that a path that dropped either would fail here. Needs the real Katrina
# file from ../shared/data.
set -euo pipefail
sl=$1 work=$2 shared=$3
storm="$shared/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc"
if [ ! -f "$storm" ]; then
  echo "scene_paths: $storm is absent (../shared/data is not beside the checkout)"
  exit 1
fi
rm -rf "$work" && mkdir -p "$work"
# The tangent point 150 km north-west of the grid's centre: the columns sink by up to 4 km.
cat > "$work/drop.json" <<JSON
{"data": "$storm", "curvature": "drop", "origin": [25.2, -90.2], "max-fields": 4,
 "sun-azimuth": 120, "sun-elevation": 25, "view-azimuth": 200, "view-elevation": 6, "fov": 50,
 "width": 96, "height": 64}
JSON
sed -e 's/"curvature": "drop", "origin": \[25.2, -90.2\], //' "$work/drop.json" > "$work/flat.json"
"$sl" render --scene "$work/drop.json" --cpu-composite --float --quiet --out "$work/render.exr"
"$sl" validate --scene "$work/drop.json" --out "$work/validate" --quick --no-plot --spp 1 --repeat 1 --quiet
"$sl" compare "$work/render.exr" "$work/validate/frame.exr" --threshold 0
"$sl" render --scene "$work/flat.json" --cpu-composite --float --quiet --out "$work/flat.exr"
if "$sl" compare "$work/flat.exr" "$work/validate/frame.exr" --threshold 0.05 > "$work/flat.txt"; then
  echo "the scene without --curvature drop and --origin draws the same frame: the test cannot tell them apart"
  cat "$work/flat.txt"
  exit 1
fi
echo "render and validate draw the same frame of the curved, re-originated scene"
