#!/usr/bin/env bash
# readme_images.sh [STORMLIGHT] [OUTDIR]: renders the README's hero image, the montage of the
# paper's figures (one bundled scene per figure, 320x240 tiles, two columns), the CM1 supercell and
# the Twomey pair of docs/DATA.md into OUTDIR, then
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

# Real thunderstorm output (the CM1 supercell, from the shared data folder beside the checkout), and
# the Twomey pair: one shallow-cumulus field with 100 and 200 droplets per cm^3 (docs/DATA.md).
"$sl" render --scene datasets/scenes/supercell.json --quiet --out "$out/supercell.exr,$out/supercell.png"
bomex=../shared/data/cm1/cm1_bomex_les50m_t090min.nc
for n in 100 200; do
  "$sl" render "$bomex" --sun-azimuth 200 --sun-elevation 40 --camera-position 2500,-4500,1800 \
    --camera-target 0,0,900 --fov 50 --droplet-number "$n" --width 400 --height 260 --exposure 8 --quiet \
    --out "$out/bomex_$n.exr,$out/bomex_$n.png"
done
"$sl" montage "$out/bomex_100.png" "$out/bomex_200.png" --columns 2 --out "$out/twomey.png"

cp "$out/cumulonimbus.png" "$out/paper_figures.png" "$out/supercell.png" "$out/twomey.png" docs/images/
echo "wrote docs/images/cumulonimbus.png, paper_figures.png, supercell.png and twomey.png (tiles in $out)"
