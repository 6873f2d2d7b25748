#!/usr/bin/env bash
# view.sh STORMLIGHT SCENES_DIR WORKDIR: drives `stormlight view` with a script (orbit by a mouse
# drag, sun moved by keys, xi raised, save), then checks that the saved scene holds the moved
# camera and sun, and that its EXR equals a batch `render --scene` of the saved scene (exactly:
# the same code draws both) and the CPU light volume within the parity tolerance.
set -euo pipefail
sl=$1 scenes=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
cat > "$work/script.txt" <<SCRIPT
# orbit 10 degrees west (a 40-pixel drag), sun 5 degrees east and 2 up, xi + 0.01, save
drag 40 0
key d
key w
key X
save $work/saved
SCRIPT
"$sl" view --scene "$scenes/fig6_halo.json" --width 64 --height 48 --script "$work/script.txt"
grep -q '"sun-azimuth":	185' "$work/saved.json" || { echo "FAIL sun azimuth not 180 + 5"; cat "$work/saved.json"; exit 1; }
grep -q '"sun-elevation":	32' "$work/saved.json" || { echo "FAIL sun elevation not 30 + 2"; exit 1; }
grep -q '"xi":	0.01' "$work/saved.json" || { echo "FAIL xi not 0 + 0.01"; exit 1; }
grep -q '"camera-position"' "$work/saved.json" || { echo "FAIL the scene's explicit camera was lost"; exit 1; }
"$sl" render --scene "$work/saved.json" --gpu --quiet --out "$work/batch.exr" 2> "$work/batch.log"
"$sl" compare "$work/saved.exr" "$work/batch.exr" --threshold 0
"$sl" render --scene "$work/saved.json" --light-volume --quiet --out "$work/cpu.exr"
"$sl" compare "$work/saved.exr" "$work/cpu.exr" --threshold 1e-3
# The orbit moved the camera: the saved view differs from the scene's own.
"$sl" render --scene "$scenes/fig6_halo.json" --width 64 --height 48 --gpu --quiet --out "$work/start.exr"
if "$sl" compare "$work/saved.exr" "$work/start.exr" --threshold 0.05 > /dev/null; then
  echo "FAIL the saved view looks like the starting one"
  exit 1
fi
echo "view: scripted orbit, sun and save reproduced by render --scene"
