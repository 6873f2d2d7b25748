#!/usr/bin/env bash
# view.sh STORMLIGHT SCENES_DIR WORKDIR: drives `stormlight view` with a script (orbit by a mouse
# drag, a pan, sun moved by keys, xi raised, march samples raised, save), then checks that the saved scene holds the moved
# camera and sun, and that its EXR equals a batch `render --scene` of the saved scene (exactly:
# the same code draws both) and the CPU light volume within the parity tolerance.
set -euo pipefail
sl=$1 scenes=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
cat > "$work/script.txt" <<SCRIPT
# orbit 10 degrees west (a 40-pixel drag), pan 6 pixels right, sun 5 degrees east and 2 up,
# xi + 0.01, march samples per cell 1 + 1, save
drag 40 0
pan 6 0
key d
key w
key X
key M
save $work/saved
SCRIPT
"$sl" view --scene "$scenes/fig6_halo.json" --width 64 --height 48 --earth flat --script "$work/script.txt"
grep -q '"sun-azimuth":	185' "$work/saved.json" || { echo "FAIL sun azimuth not 180 + 5"; cat "$work/saved.json"; exit 1; }
grep -q '"sun-elevation":	32' "$work/saved.json" || { echo "FAIL sun elevation not 30 + 2"; exit 1; }
grep -q '"xi":	0.01' "$work/saved.json" || { echo "FAIL xi not 0 + 0.01"; exit 1; }
grep -q '"camera-position"' "$work/saved.json" || { echo "FAIL the scene's explicit camera was lost"; exit 1; }
if grep -q '"camera-target":	\[0, -1000, 677\]' "$work/saved.json"; then echo "FAIL the pan did not move the target"; exit 1; fi
grep -q '"earth":	"flat"' "$work/saved.json" || { echo "FAIL an option the viewer does not change was lost"; exit 1; }
grep -q '"march-samples":	"2"' "$work/saved.json" || { echo "FAIL march samples not 1 + 1"; cat "$work/saved.json"; exit 1; }
"$sl" render --scene "$work/saved.json" --gpu --quiet --out "$work/batch.exr" 2> "$work/batch.log"
"$sl" compare "$work/saved.exr" "$work/batch.exr" --threshold 0
"$sl" render --scene "$work/saved.json" --light-volume --quiet --out "$work/cpu.exr"
"$sl" compare "$work/saved.exr" "$work/cpu.exr" --threshold 1e-3
# The orbit moved the camera: the saved view differs from the scene's own.
"$sl" render --scene "$scenes/fig6_halo.json" --width 64 --height 48 --earth flat --gpu --quiet --out "$work/start.exr"
if "$sl" compare "$work/saved.exr" "$work/start.exr" --threshold 0.05 > /dev/null; then
  echo "FAIL the saved view looks like the starting one"
  exit 1
fi
# The series and the clock: a step forward (21:00 UTC in the Katrina file) and an hour later;
# the sun then stands where render places it for that date.
printf 'key T\nkey H\nsave %s/dated\n' "$work" > "$work/dated.txt"
"$sl" view --scene "$scenes/fig9_storm_sky.json" --width 48 --height 36 --script "$work/dated.txt"
grep -q '"time":	3' "$work/dated.json" || { echo "FAIL the time step did not advance"; exit 1; }
data=$(sed -n 's/.*"data":\t"\(.*\)".*/\1/p' "$work/dated.json")
"$sl" render "$data" --scene "$scenes/fig9_storm_sky.json" --time 3 --date 2005-08-28T22:00:00Z --width 48 --height 36 \
  --gpu --quiet --out "$work/dated_batch.exr"
"$sl" compare "$work/dated.exr" "$work/dated_batch.exr" --threshold 1e-6
echo "view: scripted orbit, sun, time step, date and save reproduced by render"
