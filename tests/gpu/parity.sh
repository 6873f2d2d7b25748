#!/usr/bin/env bash
# parity.sh STORMLIGHT SCENES_DIR WORKDIR: renders the bundled scenes small with the GPU pass
# and with the CPU's light-volume path (the same method: swept light volume, ray-marched eye;
# both carry eight fields, so that cloud and rain take the same size tables)
# and compares them on linear HDR (stormlight compare: relative RMSE <= 1e-3; float against
# double and half-float EXR storage leave about 1e-4). A --gpu that fell back to the CPU fails.
# Also prints, without asserting, the GPU against the CPU's default half-angle slicer: that
# difference is between the two methods, and the CPU's light volume shows the same.
set -euo pipefail
sl=$1 scenes=$2 work=$3
mkdir -p "$work"
size=(--width 64 --height 48 --quiet)
status=0
# The CM1 scenes (the shared data beside the checkout): the supercell's six species and size tables
# in eight fields, seen from the ground (skylight, diffuse sunlight, the ground and its shadow) and
# from above the anvil; the LES cumulus field.
for scene in fig5_rainbow fig6_halo fig4_glory fig11_dawn fig9_storm_sky supercell_chaser supercell_above_anvil \
  cumulus_les_ground; do
  s="$scenes/$scene.json"
  if ! "$sl" render --scene "$s" "${size[@]}" --gpu --out "$work/$scene.gpu.exr,$work/$scene.gpu.png" \
    2> "$work/$scene.gpu.log"; then
    cat "$work/$scene.gpu.log"; exit 1
  fi
  if grep -q "rendering on the CPU" "$work/$scene.gpu.log"; then
    echo "FAIL $scene: the GPU path fell back: $(cat "$work/$scene.gpu.log")"
    status=1
    continue
  fi
  "$sl" render --scene "$s" "${size[@]}" --light-volume --out "$work/$scene.cpu.exr"
  "$sl" render --scene "$s" "${size[@]}" --out "$work/$scene.slicer.exr"
  if result=$("$sl" compare "$work/$scene.gpu.exr" "$work/$scene.cpu.exr" --threshold 1e-3 --diff "$work/$scene.diff.png")
  then echo "$scene GPU vs CPU light volume: $result"
  else echo "FAIL $scene GPU vs CPU light volume: $result"; status=1
  fi
  echo "$scene GPU vs CPU slicer (not asserted): $("$sl" compare "$work/$scene.gpu.exr" "$work/$scene.slicer.exr" --threshold 1)"
done
# The round earth of --curvature drop: the GPU's rays stop at the sphere and its sunlight is taken
# at the altitude above it, as the CPU's (Katrina seen from 30 km, 200 km from the storm: 8.4e-4
# when the GPU's rays went through the earth; 7e-6 now, as flat views).
katrina="${SL_SHARED_DIR:-}/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc"
if [ -f "$katrina" ]; then
  drop=(--time 2 --origin 22.6,-90.35 --curvature drop --camera-position 0,-60000,30000
        --camera-target 0,230000,-4000 --fov 50 --width 96 --height 72 --quiet)
  "$sl" render "$katrina" "${drop[@]}" --gpu --out "$work/drop.gpu.exr" 2> "$work/drop.gpu.log" || { cat "$work/drop.gpu.log"; exit 1; }
  "$sl" render "$katrina" "${drop[@]}" --light-volume --out "$work/drop.cpu.exr"
  if grep -q "rendering on the CPU" "$work/drop.gpu.log"; then echo "FAIL drop: the GPU path fell back"; status=1
  elif result=$("$sl" compare "$work/drop.gpu.exr" "$work/drop.cpu.exr" --threshold 1e-4)
  then echo "Katrina --curvature drop GPU vs CPU light volume: $result"
  else echo "FAIL Katrina --curvature drop GPU vs CPU light volume: $result"; status=1
  fi
else
  echo "FAIL no $katrina (the shared data beside the checkout)"; status=1
fi
# A model the GPU path does not carry (16 wavelengths) falls back to the CPU with one line.
"$sl" render --scene "$scenes/fig6_halo.json" --width 16 --height 12 --quiet --wavelengths spectral --gpu \
  --out "$work/fallback.exr" 2> "$work/fallback.log"
if [ "$(grep -c . "$work/fallback.log")" != 1 ] || ! grep -q "^render: --gpu: .*; rendering on the CPU$" "$work/fallback.log"; then
  echo "FAIL the spectral fallback did not say so in one line:"; cat "$work/fallback.log"; status=1
fi
exit $status
