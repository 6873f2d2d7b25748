#!/usr/bin/env bash
# A time series of the real Katrina file (issue 9): 4 frames and a movie; interrupted, the rerun
# renders only what is missing; 2 MPI ranks write the same bytes as one; a series frame is the
# single render of its time; a camera path from scene keys. Small images keep it to seconds.
# Usage: series.sh STORMLIGHT WORK SHARED [MPIEXEC]   (VTK composites: run under xvfb-run)
# SHARED is the shared folder beside the checkout (../shared), which holds the real data.
set -uo pipefail
sl=$1 work=$2 shared=$3 mpiexec=${4:-}
katrina=$shared/data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc
[ -f "$katrina" ] || { echo "series: no $katrina (the shared data beside the checkout)" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/check.sh"
small=(--width 48 --height 36 --slices 48 --light-resolution 64)
json_number() { grep -o "\"$2\":[0-9.]*" "$1" | head -1 | cut -d: -f2; }

# 4 frames, EXR and PNG, and the movie.
"$sl" render "$katrina" --times all --out "$work/a/k_%04d.exr,$work/a/k_%04d.png" "${small[@]}" \
  --movie "$work/a/katrina.mp4" --fps 4 --json >"$work/a.json" 2>"$work/a.err"
check "series of 4 frames exits 0" test -s "$work/a.json"
check "4 EXR and 4 PNG frames" bash -c "[ \$(ls '$work'/a/k_000[0-3].exr '$work'/a/k_000[0-3].png | wc -l) -eq 8 ]"
check "the movie has 4 frames (ffprobe)" bash -c "[ \"\$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 '$work/a/katrina.mp4')\" = 4 ]"
check "no temporary files left" bash -c "! ls -A '$work/a' | grep -q '\\.tmp\$'"
check "the frames differ in time (the sun moves, the storm moves)" bash -c "! cmp -s '$work/a/k_0000.exr' '$work/a/k_0003.exr'"
# Each frame's stages (load, draw, composite, write) are parts of its time, set-up a part of the
# rest; the frames per minute are the frames over the series' wall time.
check "each frame's stages add up to no more than its time" /usr/bin/python3 -c "
import json, sys
d = json.load(open('$work/a.json'))
t = [f['seconds'] for f in d['series']]
ok = len(t) == 4 and all(0 < s['draw'] and 0 <= s['setup'] and s['load'] + s['draw'] + s['composite'] + s['write'] + s['setup'] <= s['frame'] for s in t)
ok = ok and abs(d['frames_per_minute'] - 60 * d['rendered'] / d['seconds']) < 1e-6 * d['frames_per_minute']
sys.exit(0 if ok else 1)"

# A series keeps one world frame (the first frame's centre, where the reader has --origin): the
# single renders below are given the same one.
origin=()
o=$(grep -o '"origin":\[[^]]*\]' "$work/a.json" | sed -e 's/.*\[//' -e 's/\]//')
[ -n "$o" ] && origin=(--origin "$o")

# A series frame is the single render of that time: same file, same time, same sun from its date.
"$sl" render "$katrina" --time 2 --out "$work/single2.exr" "${small[@]}" "${origin[@]}" --quiet
check "series frame 2 = single render of time 2" cmp "$work/a/k_0002.exr" "$work/single2.exr"

# Interrupted: killed once the 2nd frame's files are in place; the rerun renders only the rest.
mkdir -p "$work/b"
"$sl" render "$katrina" --times all --out "$work/b/k_%04d.exr,$work/b/k_%04d.png" "${small[@]}" --quiet &
pid=$!
for _ in $(seq 600); do [ -e "$work/b/k_0001.png" ] && break; sleep 0.05; done
kill "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
done_before=$(ls "$work"/b/k_*.png 2>/dev/null | wc -l)
# (On a very busy machine the run may finish before the kill lands: the checks below still hold.)
check "the kill came after frame 2" bash -c "[ $done_before -ge 2 ]"
# What a killed writer leaves (sl_temp_name's ".<name>.<pid>.tmp", its process gone) and a live one's.
true & dead=$!
wait "$dead"
: > "$work/b/.k_0003.exr.$dead.tmp"
: > "$work/b/.k_0000.png.$$.tmp"
"$sl" render "$katrina" --times all --out "$work/b/k_%04d.exr,$work/b/k_%04d.png" "${small[@]}" --json >"$work/b.json"
check "the killed writer's temporary file is removed" bash -c "[ ! -e '$work/b/.k_0003.exr.$dead.tmp' ] && grep -q '\"stale_temporary_removed\":[1-9]' '$work/b.json'"
check "a live writer's temporary file is kept" bash -c "[ -e '$work/b/.k_0000.png.$$.tmp' ]"
rm -f "$work/b/.k_0000.png.$$.tmp"
check "the rerun skips the complete frames" bash -c "[ \"$(json_number "$work/b.json" skipped)\" = $done_before ]"
check "the rerun renders only the remaining ones" bash -c "[ \"$(json_number "$work/b.json" rendered)\" = $((4 - done_before)) ]"
for i in 0 1 2 3; do
  check "resumed frame $i = uninterrupted frame $i" bash -c "cmp '$work/a/k_000$i.exr' '$work/b/k_000$i.exr' && cmp '$work/a/k_000$i.png' '$work/b/k_000$i.png'"
done

# Deterministic: frames 2 and 3 removed; the rerun renders exactly those two and leaves 0, 1 alone.
touch -d '2001-01-01' "$work"/b/k_0000.* "$work"/b/k_0001.*
rm -f "$work"/b/k_0002.exr "$work"/b/k_0003.png
"$sl" render "$katrina" --times all --out "$work/b/k_%04d.exr,$work/b/k_%04d.png" "${small[@]}" --json >"$work/c.json"
check "rerun after deleting frames 2-3 renders 2" bash -c "[ \"$(json_number "$work/c.json" rendered)\" = 2 ] && [ \"$(json_number "$work/c.json" skipped)\" = 2 ]"
check "frames 0-1 untouched (mtime)" bash -c "[ -z \"\$(find '$work/b' -name 'k_000[01].*' -newermt 2001-01-02)\" ]"
check "frames 2-3 rewritten" bash -c "[ \$(find '$work/b' -name 'k_000[23].*' -newermt 2001-01-02 | wc -l) -eq 4 ]"
check "--overwrite renders all" bash -c "'$sl' render '$katrina' --times 0:1 --out '$work/b/k_%04d.exr' ${small[*]} --overwrite --json | grep -q '\"rendered\":1,'"

# Frames across MPI ranks: the same bytes as one rank.
if [ -n "$mpiexec" ]; then
  root=()
  [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
  "$mpiexec" "${root[@]}" --oversubscribe -n 2 "$sl" render "$katrina" --times all \
    --out "$work/m/k_%04d.exr,$work/m/k_%04d.png" "${small[@]}" >"$work/m.log" 2>&1
  check "mpirun -n 2 ran on 2 ranks" grep -q "on 2 ranks" "$work/m.log"
  for i in 0 1 2 3; do
    check "2 ranks = 1 rank, frame $i" bash -c "cmp '$work/a/k_000$i.exr' '$work/m/k_000$i.exr' && cmp '$work/a/k_000$i.png' '$work/m/k_000$i.png'"
  done
fi

# A camera path from key frames: frame 1 of keys at frames 0 and 3 on a straight line, looking at
# one point, sits a third of the way, which a single render given that camera reproduces.
cat >"$work/path.json" <<JSON
{"camera_keys": [
  {"time": 0, "position": [-60000, -300000, 20000], "look_at": [0, 0, 2000], "fov": 30},
  {"time": 3, "position": [60000, -300000, 20000], "look_at": [0, 0, 2000], "fov": 45}]}
JSON
"$sl" render "$katrina" --scene "$work/path.json" --times 0:2 --out "$work/p/k_%04d.exr" "${small[@]}" --json >"$work/p.json"
check "camera path frames rendered" bash -c "[ \"$(json_number "$work/p.json" rendered)\" = 2 ]"
"$sl" render "$katrina" --time 1 --camera-position -20000,-300000,20000 --camera-target 0,0,2000 --fov 35 \
  --out "$work/p1.exr" "${small[@]}" "${origin[@]}" --quiet
check "path frame 1 = the camera a third of the way" bash -c "'$sl' compare '$work/p1.exr' '$work/p/k_0001.exr' --threshold 1e-5"

# Clear one-line errors, nothing written.
check "several frames need a numbered pattern" bash -c "! '$sl' render '$katrina' --times all --out '$work/e/x.exr' 2>'$work/e.err' && grep -q 'numbered pattern' '$work/e.err' && [ ! -e '$work/e' ]"
check "--movie needs PNG frames" bash -c "! '$sl' render '$katrina' --times all --out '$work/e/x_%d.exr' --movie '$work/e/m.mp4' 2>'$work/e.err' && grep -q 'PNG frames' '$work/e.err'"
check "bad --times" bash -c "! '$sl' render '$katrina' --times 3:9 --out '$work/e/x_%d.exr' 2>'$work/e.err' && grep -q -- '--times' '$work/e.err'"
check "--movie without ffmpeg" bash -c "! PATH=/nonexistent '$sl' render '$katrina' --times all --out '$work/e/x_%d.png' --movie '$work/e/m.mp4' 2>'$work/e.err' && grep -q 'needs ffmpeg' '$work/e.err'"

echo "series: $passes passed, $failures failed"
[ $failures -eq 0 ]
