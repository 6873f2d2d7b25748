#!/usr/bin/env bash
# The CLI's front door: --version, --help on every subcommand, synth -> info -> render -> compare.
set -uo pipefail
sl=$1 work=$2 datasets=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/check.sh"
check "--version" bash -c "'$sl' --version | grep -q '^stormlight [0-9]'"
check "--help lists commands" bash -c "'$sl' --help | grep -q render"
for cmd in $("$sl" --help | awk '/^commands:/{on=1;next} on && NF==0 {exit} on {print $1}'); do
  check "$cmd --help" bash -c "'$sl' $cmd --help | grep -q '^usage: stormlight $cmd'"
done
check "synth is seeded" bash -c "'$sl' synth cirrus --nx 8 --ny 8 --nz 6 --seed 7 --out '$work/a.nc' && '$sl' synth cirrus --nx 8 --ny 8 --nz 6 --seed 7 --out '$work/b.nc' && cmp <(ncdump '$work/a.nc' | tail -n +2) <(ncdump '$work/b.nc' | tail -n +2)"
check "different seeds differ" bash -c "'$sl' synth cirrus --nx 8 --ny 8 --nz 6 --seed 8 --out '$work/c.nc' && ! cmp -s <(ncdump -v QICE '$work/a.nc' | tail -n +2) <(ncdump -v QICE '$work/c.nc' | tail -n +2)"
check "info --json is one object" bash -c "'$sl' info '$datasets/cumulonimbus.nc' --json | grep -qE '^\{.*\"west_east\":48.*\}$'"
check "render then compare to itself" bash -c "'$sl' render '$datasets/cirrus.nc' --out '$work/f.exr' --width 64 --height 48 --slices 64 --cpu-composite --quiet && '$sl' compare '$work/f.exr' '$work/f.exr' --json | grep -q '\"pass\":true'"
check "compare fails above threshold" bash -c "'$sl' render '$datasets/cirrus.nc' --out '$work/g.exr' --width 64 --height 48 --slices 64 --cpu-composite --quiet --sun-elevation 10 --sun-azimuth 200 && ! '$sl' compare '$work/f.exr' '$work/g.exr' --threshold 0.001"
check "the sun from --date over the grid" bash -c "'$sl' render '$datasets/cirrus.nc' --out '$work/d.exr' --width 32 --height 24 --slices 32 --cpu-composite --date 2024-04-10T10:00:00Z | grep -q 'sun at 2024-04-10 10:00 UTC'"
check "night is reported, not NaN" bash -c "'$sl' render '$datasets/cirrus.nc' --out '$work/n.exr' --width 32 --height 24 --slices 32 --cpu-composite --date 2024-04-10T23:00:00Z | grep -q '^night'"
# Without Times, the dates come from XTIME's units (real files often lack Times).
ncdump "$datasets/cirrus.nc" | sed -e '/char Times(/d' -e '/^ *Times =/,/;/d' -e 's/^variables:/variables:\n\tfloat XTIME(Time) ;\n\t\tXTIME:units = "minutes since 2024-04-10 09:30:00" ;/' -e 's/^data:/data:\n XTIME = 30 ;/' >"$work/noTimes.cdl"
ncgen -4 -o "$work/noTimes.nc" "$work/noTimes.cdl" 2>"$work/ncgen.err"
check "times from XTIME" bash -c "'$sl' info '$work/noTimes.nc' --json | grep -q '\"times\":\\[\"2024-04-10_10:00:00\"\\]'"
echo "basics: $passes passed, $failures failed"
[ $failures -eq 0 ]
