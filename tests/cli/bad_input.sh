#!/usr/bin/env bash
# Bad input gets one clear line naming the file and the problem, a non-zero exit, and no output
# file (not even a temporary one). Malformed storms are written from CDL with ncgen.
set -uo pipefail
sl=$1 work=$2 datasets=$3
rm -rf "$work" && mkdir -p "$work/out"
failures=0 passes=0

# expect_failure NAME PATTERN COMMAND...: non-zero exit, one stderr line matching PATTERN, out/ empty.
expect_failure() {
  local name=$1 pattern=$2
  shift 2
  "$@" >"$work/stdout" 2>"$work/stderr"
  local rc=$? lines
  lines=$(wc -l <"$work/stderr")
  if [ $rc -ne 0 ] && [ "$lines" -eq 1 ] && grep -qE "$pattern" "$work/stderr" && [ -z "$(ls -A "$work/out")" ]; then
    passes=$((passes + 1))
  else
    failures=$((failures + 1))
    echo "FAILED: $name (exit $rc, $lines stderr lines, out/: $(ls -A "$work/out" | tr '\n' ' '))"
    sed 's/^/  stderr: /' "$work/stderr"
  fi
  rm -f "$work/out/"* "$work/out/".* 2>/dev/null
}

# A tiny valid WRF-style file as CDL, with switches to break it.
cdl() {
  local omit=${1:-} bad_shape=${2:-} nan=${3:-}
  cat <<CDL
netcdf tiny {
dimensions:
  Time = UNLIMITED ; DateStrLen = 19 ; west_east = 2 ; south_north = 2 ; bottom_top = 2 ; bottom_top_stag = 3 ;
variables:
  char Times(Time, DateStrLen) ;
  float P(Time, bottom_top, south_north, west_east) ;
  float PB(Time, bottom_top, south_north, west_east) ;
  $( [ "$bad_shape" = T ] && echo "float T(Time, bottom_top_stag, south_north, west_east) ;" || echo "float T(Time, bottom_top, south_north, west_east) ;" )
  float QVAPOR(Time, bottom_top, south_north, west_east) ;
  float PH(Time, bottom_top_stag, south_north, west_east) ;
  float PHB(Time, bottom_top_stag, south_north, west_east) ;
  float HGT(Time, south_north, west_east) ;
  float XLAT(Time, south_north, west_east) ;
  float XLONG(Time, south_north, west_east) ;
  $( [ "$omit" = Q ] || echo "float QCLOUD(Time, bottom_top, south_north, west_east) ;" )
  $( [ "$omit" = Q ] || echo "float QRAIN(Time, bottom_top, south_north, west_east) ;" )
  :DX = 1000.f ; :DY = 1000.f ; :MAP_PROJ = 1 ; :MP_PHYSICS = 4 ;
data:
  Times = "2024-06-15_22:00:00" ;
  P = 0, 0, 0, 0, 0, 0, 0, 0 ;
  PB = 90000, 90000, 90000, 90000, 80000, 80000, 80000, 80000 ;
  $( [ "$bad_shape" = T ] && echo "T = 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0 ;" || echo "T = 0, 0, 0, 0, 0, 0, 0, 0 ;" )
  QVAPOR = 0.005, 0.005, 0.005, 0.005, 0.003, 0.003, 0.003, 0.003 ;
  PH = 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0 ;
  PHB = 0, 0, 0, 0, 9810, 9810, 9810, 9810, 19620, 19620, 19620, 19620 ;
  HGT = 0, 0, 0, 0 ;
  XLAT = 35, 35, 35.01, 35.01 ;
  XLONG = -97, -96.99, -97, -96.99 ;
  $( [ "$omit" = Q ] || { [ "$nan" = 1 ] && echo "QCLOUD = 0.001, NaN, 0.001, 0.001, 0, 0, 0, 0 ;" || echo "QCLOUD = 0.001, 0.001, 0.001, 0.001, 0, 0, 0, 0 ;"; } )
  $( [ "$omit" = Q ] || echo "QRAIN = 0.0005, -1e-12, 0, 0, 0, 0, 0, 0 ;" )
}
CDL
}
make_nc() { cdl "$@" >"$work/tmp.cdl" && ncgen -4 -o "$work/$name.nc" "$work/tmp.cdl"; }
name=good; make_nc "" "" ""
name=no_hydrometeors; make_nc Q "" ""
name=wrong_shape; make_nc "" T ""
name=nan_field; make_nc "" "" 1
# P alone missing: drop its declaration and data.
cdl "" "" "" | grep -v -E "^\s*(float P\(|P = )" >"$work/nop.cdl" && ncgen -4 -o "$work/no_p.nc" "$work/nop.cdl"
# Variants of the good file: an unsupported projection; no time records (declarations only);
# an absurd grid (60000 x 60000 columns, nothing written: netCDF-4 stores no unwritten chunks);
# a dimension beyond any model; a truncated netCDF-3 copy (its header intact, its data cut).
cdl "" "" "" | sed 's/:MAP_PROJ = 1/:MAP_PROJ = 5/' >"$work/proj.cdl" && ncgen -4 -o "$work/bad_proj.nc" "$work/proj.cdl"
cdl "" "" "" | awk '/^data:/ {print; print "}"; exit} {print}' >"$work/zero.cdl" && ncgen -4 -o "$work/zero_times.nc" "$work/zero.cdl"
cdl "" "" "" | sed 's/west_east = 2 ; south_north = 2/west_east = 60000 ; south_north = 60000/' |
  awk '/^data:/ {print; print "  Times = \"2024-06-15_22:00:00\" ;"; print "}"; exit} {print}' >"$work/huge.cdl" &&
  ncgen -4 -o "$work/huge_grid.nc" "$work/huge.cdl"
cdl "" "" "" | sed 's/west_east = 2 ;/west_east = 200000 ;/' |
  awk '/^data:/ {print; print "}"; exit} {print}' >"$work/wide.cdl" && ncgen -4 -o "$work/absurd_dim.nc" "$work/wide.cdl"
nccopy -k classic "$work/good.nc" "$work/good3.nc"
head -c $(( $(stat -c %s "$work/good3.nc") - 40 )) "$work/good3.nc" >"$work/truncated3.nc"
echo "this is not a NetCDF file" >"$work/text.nc"
printf '{"data": "good.nc", "colour": 3}\n' >"$work/bad_scene.json"
head -c 20000 "$datasets/cumulonimbus.nc" >"$work/truncated.nc"

out="$work/out/frame.exr,$work/out/frame.png"
expect_failure "missing file" "nonexistent.nc" "$sl" render "$work/nonexistent.nc" --out "$out" --cpu-composite
expect_failure "not NetCDF" "text.nc.*not a NetCDF" "$sl" render "$work/text.nc" --out "$out" --cpu-composite
expect_failure "truncated NetCDF" "truncated.nc" "$sl" render "$work/truncated.nc" --out "$out" --cpu-composite
expect_failure "missing variable P" "no_p.nc.*missing variable 'P'" "$sl" render "$work/no_p.nc" --out "$out" --cpu-composite
expect_failure "wrong dimensions" "wrong_shape.nc.*'T'" "$sl" render "$work/wrong_shape.nc" --out "$out" --cpu-composite
expect_failure "NaN in a field" "nan_field.nc.*QCLOUD.*NaN" "$sl" render "$work/nan_field.nc" --out "$out" --cpu-composite
expect_failure "unknown option" "unknown option --bogus" "$sl" render "$work/good.nc" --out "$out" --bogus 1
expect_failure "unknown command" "unknown command" "$sl" renderr "$work/good.nc"
expect_failure "unwritable output" "nonexistent-dir" "$sl" render "$work/good.nc" --out "$work/nonexistent-dir/x.png" --cpu-composite
expect_failure "bad output type" "must end in .exr or .png" "$sl" render "$work/good.nc" --out "$work/out/x.jpg" --cpu-composite
expect_failure "absurd size" "width" "$sl" render "$work/good.nc" --out "$out" --width 0 --cpu-composite
expect_failure "absurd slices" "slices" "$sl" render "$work/good.nc" --out "$out" --slices 999999 --cpu-composite
expect_failure "no march samples" "march-samples" "$sl" render "$work/good.nc" --out "$out" --light-volume --march-samples 0 --cpu-composite
expect_failure "too many march samples" "march-samples" "$sl" render "$work/good.nc" --out "$out" --light-volume --march-samples 9 --cpu-composite
expect_failure "thin-step depth above 1" "march-thin-depth" "$sl" render "$work/good.nc" --out "$out" --light-volume --march-thin-depth 2 --cpu-composite
expect_failure "thin steps on the GPU pass" "march-thin-depth" "$sl" render "$work/good.nc" --out "$out" --gpu --march-thin-depth 0.3
expect_failure "refinement tolerance above 1" "march-refine" "$sl" render "$work/good.nc" --out "$out" --light-volume --march-refine 2 --cpu-composite
expect_failure "adaptive pixels on the GPU pass" "march-refine" "$sl" render "$work/good.nc" --out "$out" --gpu --march-refine 0.05
expect_failure "overlays on the CPU composite" "cpu-composite draws no overlay lines" "$sl" render "$work/good.nc" --out "$out" --graticule --cpu-composite
expect_failure "negative fog visibility" "fog-visibility-km" "$sl" render "$work/good.nc" --out "$out" --fog-visibility-km -1 --cpu-composite
expect_failure "unknown scene key" "bad_scene.json.*unknown scene key 'colour'" "$sl" render --scene "$work/bad_scene.json" --out "$out" --cpu-composite
expect_failure "scene not JSON" "text.nc.*not a JSON object" "$sl" render --scene "$work/text.nc" --out "$out" --cpu-composite
expect_failure "time out of range" "time index 3" "$sl" render "$work/good.nc" --out "$out" --time 3 --cpu-composite
expect_failure "info on text" "text.nc" "$sl" info "$work/text.nc"
expect_failure "no hydrometeors" "no_hydrometeors.nc.*no hydrometeor variables" "$sl" info "$work/no_hydrometeors.nc" --json
expect_failure "no hydrometeors (render)" "no_hydrometeors.nc.*no hydrometeor variables" "$sl" render "$work/no_hydrometeors.nc" --out "$out" --cpu-composite
expect_failure "unsupported projection" "bad_proj.nc.*unsupported map projection MAP_PROJ=5" "$sl" render "$work/bad_proj.nc" --out "$out" --cpu-composite
expect_failure "zero time records" "zero_times.nc.*no time records" "$sl" render "$work/zero_times.nc" --out "$out" --cpu-composite
expect_failure "absurd grid size" "huge_grid.nc.*needs about .* GB.*--region" "$sl" render "$work/huge_grid.nc" --out "$out" --cpu-composite
expect_failure "absurd dimension" "absurd_dim.nc.*west_east.*absurd" "$sl" info "$work/absurd_dim.nc"
expect_failure "truncated netCDF-3" "truncated3.nc: truncated" "$sl" render "$work/truncated3.nc" --out "$out" --cpu-composite
expect_failure "over --max-memory" "good.nc.*more than --max-memory.*--stride" "$sl" render "$work/good.nc" --out "$out" --max-memory 100 --cpu-composite
expect_failure "bad --max-memory" "max-memory" "$sl" render "$work/good.nc" --out "$out" --max-memory lots --cpu-composite
expect_failure "bad --field type" "field: 'sleet=QRAIN'" "$sl" render "$work/good.nc" --out "$out" --field sleet=QRAIN --cpu-composite
expect_failure "bad --particles" "particles: 'some'" "$sl" render "$work/good.nc" --out "$out" --particles some --cpu-composite
expect_failure "bad --droplet-number" "droplet-number" "$sl" render "$work/good.nc" --out "$out" --droplet-number -3 --cpu-composite
expect_failure "--max-fields 0" "max-fields" "$sl" render "$work/good.nc" --out "$out" --max-fields 0 --cpu-composite
expect_failure "--max-fields 9" "max-fields" "$sl" render "$work/good.nc" --out "$out" --max-fields 9 --cpu-composite
expect_failure "--field variable missing" "good.nc.*no variable 'QGRAUP'" "$sl" info "$work/good.nc" --field snow=QGRAUP
expect_failure "--region outside the grid" "good.nc.*holds no grid column" "$sl" render "$work/good.nc" --out "$out" --region 50,51,10,11 --cpu-composite
expect_failure "bad --levels" "levels" "$sl" render "$work/good.nc" --out "$out" --levels 3:1 --cpu-composite
expect_failure "--levels beyond the model" "good.nc.*--levels 0:5 outside" "$sl" info "$work/good.nc" --levels 0:5
expect_failure "compare missing" "nope.exr" "$sl" compare "$work/nope.exr" "$work/nope2.exr"
expect_failure "compare not EXR" "text.nc" "$sl" compare "$work/text.nc" "$work/text.nc"
expect_failure "synth unknown kind" "unknown storm kind" "$sl" synth tornado --out "$work/out/x.nc"
expect_failure "synth unwritable" "nonexistent-dir" "$sl" synth cirrus --out "$work/nonexistent-dir/x.nc"

# The good file works, and its tiny negative QRAIN is clamped and counted, not an error.
if "$sl" info "$work/good.nc" --json | grep -q '"QRAIN":{[^}]*"negative_clamped":1'; then
  passes=$((passes + 1))
else
  failures=$((failures + 1))
  echo "FAILED: negative mixing ratio clamped and counted"
  "$sl" info "$work/good.nc" --json
fi
# --field moves a variable to another particle type (info and render take the same options).
if "$sl" info "$work/good.nc" --json --field snow=QRAIN | grep -q '"variable":"QRAIN","kind":"rain","type":"snow"'; then
  passes=$((passes + 1))
else
  failures=$((failures + 1))
  echo "FAILED: --field snow=QRAIN feeds snow from QRAIN"
  "$sl" info "$work/good.nc" --json --field snow=QRAIN
fi
# netCDF-3 and netCDF-4 of the same data give the same frame.
if "$sl" render "$work/good.nc" --out "$work/f4.exr" --cpu-composite --quiet --width 32 --height 32 --sun-azimuth 200 --sun-elevation 30 &&
  "$sl" render "$work/good3.nc" --out "$work/f3.exr" --cpu-composite --quiet --width 32 --height 32 --sun-azimuth 200 --sun-elevation 30 &&
  "$sl" compare "$work/f3.exr" "$work/f4.exr" --threshold 0 >/dev/null; then
  passes=$((passes + 1))
else
  failures=$((failures + 1))
  echo "FAILED: netCDF-3 and netCDF-4 copies render the same frame"
fi
echo "bad_input: $passes passed, $failures failed"
[ $failures -eq 0 ]
