#!/bin/bash
# The fast model against the Monte Carlo reference on the real CM1 storms (docs/ACCURACY.md, "A real
# thunderstorm"): the supercell at two suns (datasets/scenes/supercell.json, supercell_high_sun.json)
# and the LES cumulus field from the ground (cumulus_les_ground.json), every setting of `validate`
# with its speed-against-error chart, the skylight on in both renderers (the scenes' default).
# Each scene at 96x60 in 2x2 blocks, its reference given SECONDS of wall time (whole passes).
#
#   scripts/validate_cm1.sh [OUT [SECONDS]]     about 3 SECONDS + 3 min on 2 cores; prints the summary
#
# Needs ../shared/data/cm1 beside the checkout, jq and xvfb-run.
set -euo pipefail
cd "$(dirname "$0")/.."
S=${STORMLIGHT:-build/release/app/stormlight}
scenes="supercell supercell_high_sun cumulus_les_ground"

summary() {
  local out=$1
  echo "| scene | blocks thin / dense / shadowed | reference spp, s | noise (mean rel.) thin, dense, shadowed | scene's setting: mean rel. error thin, dense, shadowed (bias) | rel. RMSE (noise) | s/frame, speed-up | best ≤ 0.1 s: setting, rel. RMSE, speed-up |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
  for s in $scenes; do
    local r=$out/$s/report.json
    [ -f "$r" ] || continue
    jq -r --arg name "$s" '
      def f: if . == null then "—" else (. * 100 | round / 100 | tostring) end;
      def mean(c): if c.pixels > 0 then (c.mean_relative_error | f) else "—" end;
      def noise(c): if c.pixels > 0 then (c.reference_noise_mean | f) else "—" end;
      (.settings[] | select(.family == "scene")) as $s
      | "| \($name) | \($s.thin.pixels) / \($s.dense.pixels) / \($s.shadowed.pixels) | \(.reference.spp), \(.reference.seconds | round) | "
        + "\(noise($s.thin)), \(noise($s.dense)), \(noise($s.shadowed)) | "
        + "\(mean($s.thin)), \(mean($s.dense)), \(mean($s.shadowed)) (\($s.all.bias | f)) | "
        + "\($s.all.relative_rmse | f) (\($s.all.reference_noise_rmse | f)) | \($s.seconds * 1000 | round / 1000), ×\($s.speedup | round) | "
        + "\(if .best_interactive then "\(.best_interactive.name), \(.best_interactive.relative_rmse | f), ×\(.best_interactive.speedup | round)" else "none" end) |"' "$r"
  done
}

OUT=${1:-validate_cm1} SECONDS_REF=${2:-150}
mkdir -p "$OUT"
for s in $scenes; do
  echo "== $s $(date +%T), load $(cut -d' ' -f1-3 /proc/loadavg)"
  xvfb-run -a "$S" validate --scene "datasets/scenes/$s.json" --width 96 --height 60 --spp 100000000 \
    --seconds "$SECONDS_REF" --block 2 --quiet --out "$OUT/$s"
  cp "$OUT/$s/speed_error.png" "docs/images/validate_${s}_speed_error.png"
done
summary "$OUT"
