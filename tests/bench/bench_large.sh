#!/bin/sh
# A large WRF-like storm as a user meets it (docs/PERFORMANCE.md, "A large storm"): `stormlight
# synth KIND` (default cumulonimbus; stratocumulus is a deck over the whole domain) at NX x NY x NZ
# (default 1000 x 1000 x 80, 500 m), then one 1920x1080 frame:
# the load, each stage, the whole command's wall time and its peak memory against the fields'
# float size, on the file's grid and on the uniform grid the loader resamples to (the species that
# hold anything; also all the hydrometeor variables of the file, empty ones too). Run under
# xvfb-run -a. Prints; never fails on a number. Needs about 4 GB of memory and 260 MB of disk.
# usage: tests/bench/bench_large.sh [BUILD_DIR] [NX NY NZ] [KIND]
set -eu
build=${1:-build/release}
nx=${2:-1000}
ny=${3:-1000}
nz=${4:-80}
kind=${5:-cumulonimbus}
sl="$build/app/stormlight"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
/usr/bin/python3 - "$sl" "$out" "$nx" "$ny" "$nz" "$kind" <<'PY'
import os, re, subprocess, sys, time
sl, out, nx, ny, nz, kind = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), sys.argv[6]
nc = out + "/large.nc"
t0 = time.time()
subprocess.run([sl, "synth", kind, "--out", nc, "--nx", str(nx), "--ny", str(ny), "--nz", str(nz),
                "--dx", "500"], check=True, stdout=subprocess.DEVNULL)
print("synth %s %dx%dx%d: %.1f s" % (kind, nx, ny, nz, time.time() - t0))
info = subprocess.run([sl, "info", nc], check=True, capture_output=True, text=True).stdout
u = re.search(r"uniform\s+(\d+) x (\d+) x (\d+) samples", info)
# The species the storm holds: a variable that is zero everywhere is dropped by the load.
maxima = re.findall(r"^  Q\w+\s+min\s+\S+\s+max\s+(\S+)", info, re.M)
species = sum(float(m) > 0.0 for m in maxima)
file_gb = nx * ny * nz * species * 4 / 1e9
all_gb = nx * ny * nz * len(maxima) * 4 / 1e9
uniform_gb = int(u.group(1)) * int(u.group(2)) * int(u.group(3)) * species * 4 / 1e9
print("fields: %d species as floats: %.2f GB on the file's grid, %.2f GB on the uniform %s x %s x %s"
      % (species, file_gb, uniform_gb, u.group(1), u.group(2), u.group(3)))
t0 = time.time()
# The render's own peak (wait4's usage of that child alone: RUSAGE_CHILDREN would take the largest
# of every child, synth's included).
render = subprocess.Popen([sl, "render", nc, "--out", out + "/large.exr", "--width", "1920", "--height", "1080",
                           "--overwrite"], stdout=open(out + "/render.txt", "w"))
_, status, usage = os.wait4(render.pid, 0)
wall = time.time() - t0
if status != 0:
    sys.exit("render failed with status %d" % status)
peak_gb = usage.ru_maxrss * 1024 / 1e9
line = [l for l in open(out + "/render.txt").read().splitlines() if l.startswith("rendered")][0]
print(line)
stages = {k: float(v) for k, v in re.findall(r"(load|skylight|light pass|eye pass|composite|write) ([\d.]+) s", line)}
rest = wall - sum(stages.values())
print("whole command %.1f s: load %.1f, passes %.1f (light %.1f, eye %.1f), composite %.1f, write %.1f, the rest %.1f s"
      % (wall, stages["load"], stages["light pass"] + stages["eye pass"], stages["light pass"], stages["eye pass"],
         stages["composite"], stages["write"], rest))
print("peak memory %.2f GB: %.2f x the fields on the file's grid, %.2f x on the uniform grid; "
      "%.2f x all %d hydrometeor variables of the file (the empty ones too) as floats"
      % (peak_gb, peak_gb / file_gb, peak_gb / uniform_gb, peak_gb / all_gb, len(maxima)))
PY
