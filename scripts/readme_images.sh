#!/usr/bin/env bash
# readme_images.sh [STORMLIGHT] [OUTDIR]: renders the README's hero image and the montage of the
# paper's figures (one bundled scene per figure, 320x240 tiles, two columns) into OUTDIR, then
# copies them to docs/images. Run after a change that moves pixels (optics, lighting, sky), so
# that the README shows what the code renders. Needs an X display for the VTK composite
# (run it under xvfb-run -a).
set -euo pipefail
sl=${1:-build/release/app/stormlight}
out=${2:-out/readme}
mkdir -p "$out"

"$sl" render --scene datasets/scenes/default.json --quiet --out "$out/cumulonimbus.exr,$out/cumulonimbus.png"

# The montage's order is the README's caption's: Fig. 5, 6, 4, 11, 9, 10, then Fig. 13's two
# lightings of one view.
tiles=()
tile() { # NAME SCENE [FLAGS...]
  local name=$1 scene=$2
  shift 2
  "$sl" render --scene "datasets/scenes/$scene.json" --width 320 --height 240 --quiet "$@" \
    --out "$out/$name.exr,$out/$name.png"
  tiles+=("$out/$name.png")
}
tile fig5 fig5_rainbow
tile fig6 fig6_halo
tile fig4 fig4_glory
tile fig11 fig11_dawn
tile fig9 fig9_storm_sky
tile fig10 fig10_storm_nosky
tile fig13_multiple fig13_low_albedo --lighting multiple
tile fig13_low_albedo fig13_low_albedo
"$sl" montage "${tiles[@]}" --columns 2 --out "$out/paper_figures.png"

cp "$out/cumulonimbus.png" "$out/paper_figures.png" docs/images/
echo "wrote docs/images/cumulonimbus.png and docs/images/paper_figures.png (tiles in $out)"
