#!/usr/bin/env bash
# readme_images.sh [STORMLIGHT] [OUTDIR]: renders the README's hero image (the CM1 supercell), the
# montage of the paper's figures (the supercell where it shows them, 320x240 tiles, two columns), the
# first command's synthetic cumulonimbus, the supercell at sunset, the LES cumulus field and the
# Twomey pair of docs/DATA.md into OUTDIR, then
# copies them to docs/images. Run after a change that moves pixels (optics, lighting, sky), so
# that the README shows what the code renders. Needs an X display for the VTK composite
# (run it under xvfb-run -a).
set -euo pipefail
sl=${1:-build/release/app/stormlight}
out=${2:-out/readme}
mkdir -p "$out"

"$sl" render --scene datasets/scenes/default.json --quiet --out "$out/cumulonimbus.exr,$out/cumulonimbus.png"

# The montage's order is the README's caption's: Fig. 5, 6, 4, 11, 9, 10, then Fig. 13's two
# lightings of one view. Every tile is the CM1 supercell at 70 minutes (the shared data folder
# beside the checkout); the halo is on the thin eastern edge of its anvil, under a morning sun.
tiles=()
tile() { # NAME SCENE [FLAGS...]
  local name=$1 scene=$2
  shift 2
  "$sl" render --scene "datasets/scenes/$scene.json" --width 320 --height 240 --quiet "$@" \
    --out "$out/$name.exr,$out/$name.png"
  tiles+=("$out/$name.png")
}
tile fig5 supercell_rainbow
tile fig6 supercell_halo
tile fig4 supercell_above_anvil
tile fig11 supercell_sunset
tile fig9 supercell_high_sun
tile fig10 supercell_high_sun --no-atmosphere
tile fig13_multiple supercell
tile fig13_low_albedo supercell --lighting low-albedo
"$sl" montage "${tiles[@]}" --columns 2 --out "$out/paper_figures.png"

# Real thunderstorm output (the CM1 supercell, from the shared data folder beside the checkout), and
# the Twomey pair: one shallow-cumulus field with 100 and 200 droplets per cm^3 (docs/DATA.md).
"$sl" render --scene datasets/scenes/supercell_chaser.json --quiet --out "$out/supercell_chaser.exr,$out/supercell_chaser.png"
"$sl" render --scene datasets/scenes/supercell.json --quiet --out "$out/supercell.exr,$out/supercell.png"
"$sl" render --scene datasets/scenes/supercell_sunset.json --quiet --out "$out/supercell_sunset.exr,$out/supercell_sunset.png"
"$sl" render --scene datasets/scenes/cumulus_les_ground.json --quiet --out "$out/cumulus_les.exr,$out/cumulus_les.png"
bomex=../shared/data/cm1/cm1_bomex_les50m_t090min.nc
for n in 100 200; do
  "$sl" render "$bomex" --sun-azimuth 200 --sun-elevation 40 --camera-position 2500,-4500,1800 \
    --camera-target 0,0,900 --fov 50 --droplet-number "$n" --width 400 --height 260 --exposure 8 --quiet \
    --out "$out/bomex_$n.exr,$out/bomex_$n.png"
done
"$sl" montage "$out/bomex_100.png" "$out/bomex_200.png" --columns 2 --out "$out/twomey.png"

cp "$out/cumulonimbus.png" "$out/paper_figures.png" "$out/supercell_chaser.png" "$out/supercell.png" "$out/supercell_sunset.png" \
  "$out/cumulus_les.png" "$out/twomey.png" docs/images/
echo "wrote docs/images/cumulonimbus.png, paper_figures.png, supercell_chaser.png, supercell.png, supercell_sunset.png, cumulus_les.png and twomey.png (tiles in $out)"
