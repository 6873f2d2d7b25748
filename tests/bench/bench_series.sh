#!/bin/sh
# What a time series costs as a user runs it (docs/PERFORMANCE.md, "A time series"): the CM1
# supercell's 13 times (../shared/data/cm1) at 1280x720 in one `stormlight render --times all`,
# frames per minute and per frame its stages against the draw (the light and eye passes, the
# resolve and the sky); its peer in the same run, the first three times as three separate
# `stormlight render` commands, each paying start-up, tables, renderer and VTK's window again.
# Run under xvfb-run -a (VTK composites). Prints; never fails on a number.
# usage: tests/bench/bench_series.sh [BUILD_DIR] [CM1_DIR] [WIDTH HEIGHT]
set -eu
build=${1:-build/release}
data=${2:-../shared/data/cm1}
width=${3:-1280}
height=${4:-720}
sl="$build/app/stormlight"
scene=datasets/scenes/supercell_timelapse.json
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
files=$(ls "$data"/cm1_supercell_t*min.nc)
echo "series: $(echo "$files" | wc -l) times of the CM1 supercell at ${width}x${height}"
# The particle tables of each new size (the two-moment rain and hail radii change from time to
# time) are built once and kept on disk: a first series builds them (an empty cache here), a
# second one finds them.
export SL_CACHE_DIR="$out/cache"
for run in "first (tables built)" "again (tables cached)"; do
  echo "-- $run"
  # shellcheck disable=SC2086
  "$sl" render $files --scene "$scene" --times all --out "$out/s_%04d.exr" --width "$width" --height "$height" \
    --overwrite --json > "$out/series.json"
  /usr/bin/python3 - "$out/series.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
frames = [f["seconds"] for f in d["series"] if "seconds" in f]
n = len(frames)
mean = lambda k: sum(f[k] for f in frames) / n
other = sum(f["frame"] - f["load"] - f["draw"] - f["composite"] - f["write"] for f in frames) / n
print("series: %d frames in %.1f s, %.1f frames per minute" % (d["rendered"], d["seconds"], d["frames_per_minute"]))
print("per frame: %.2f s = load %.2f + draw %.2f + composite %.2f + write %.2f + other %.2f s (set-up %.2f)"
      % (mean("frame"), mean("load"), mean("draw"), mean("composite"), mean("write"), other, mean("setup")))
print("other / draw: %.1f %%; load / draw %.1f %%; composite / draw %.1f %%"
      % (100 * other / mean("draw"), 100 * mean("load") / mean("draw"), 100 * mean("composite") / mean("draw")))
first = [f["seconds"]["frame"] for f in d["series"][:3]]
print("series frames 0-2: %s s" % ", ".join("%.2f" % s for s in first))
open(sys.argv[1] + ".first3", "w").write("%.3f" % sum(first))
PY
done
# The peer: the same three times, one command each, as a user without --times would run them
# (the tables cached, as for the second series),
# from the scene less its camera path (the camera each frame had in the series given instead).
/usr/bin/python3 -c "
import json; d = json.load(open('$scene')); d.pop('camera_keys'); d.pop('data')
json.dump(d, open('$out/one.json', 'w'))"
start=$(date +%s.%N)
i=0
for f in $(echo "$files" | head -3); do
  # The camera the series' path gives frame i (its JSON), so that the frames match.
  cam=$(/usr/bin/python3 -c "import json,sys; c=json.load(open('$out/series.json'))['series'][$i]['camera']; print(','.join(map(repr,c['position'])), ','.join(map(repr,c['look_at'])), c.get('fov', 45))")
  set -- $cam
  "$sl" render "$f" --scene "$out/one.json" --out "$out/one_$i.exr" --width "$width" --height "$height" --overwrite --quiet \
    --camera-position "$1" --camera-target "$2" --fov "$3"
  i=$((i + 1))
done
end=$(date +%s.%N)
/usr/bin/python3 -c "
w = $end - $start; s = float(open('$out/series.json.first3').read())
print('three separate commands: %.2f s; the series paid %.2f s for them: separate / series %.2f' % (w, s, w / s))"
