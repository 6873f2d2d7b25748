#!/bin/bash
# The fast model against the Monte Carlo reference on every bundled scene (issue 7; docs/ACCURACY.md,
# "Every bundled scene"). Each scene is validated at 96x72 (the scene's camera and field of view,
# fewer pixels) in 2x2 blocks, its reference given SECONDS of wall time (whole passes).
#
#   scripts/validate_all.sh [OUT [SECONDS]]     run everything (about 45 min on 2 loaded cores)
#   scripts/validate_all.sh --summary OUT       only the cross-scene summary of earlier runs
#
# Scenes whose volume layer is another scene's (fig13: default's view with the low-albedo model as
# its own setting; fog_glow and haze_sun: fog_clear's view, the glow being an image-space step after
# the volume layer) reuse that scene's reference with --ref. Needs jq and xvfb-run.
set -euo pipefail
cd "$(dirname "$0")/.."
S=${STORMLIGHT:-build/release/app/stormlight}

summary() {
  local out=$1
  echo "| scene | px / blocks thin, dense | reference spp, s | ref. noise thin, dense | scene's setting: rel. RMSE thin, dense | noise removed thin, dense | xi 0: thin, dense | best ≤ 0.1 s (RMSE, speed-up) | lowest over xi |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  for d in "$out"/*/; do
    local r=$d/report.json
    [ -f "$r" ] || continue
    jq -r --arg name "$(basename "$d")" '
      def f: if . == null then "–" else (. * 1000 | round / 1000 | tostring) end;
      def row(n): (.settings[] | select(.name == n));
      (.settings[] | select(.family == "scene")) as $s
      | ([.settings[] | select(.xi == 0 and (.family == "xi" or .family == "scene"))][0]) as $x
      | "| \($name) | \(.width)×\(.height) / \($s.thin.pixels), \($s.dense.pixels) | \(.reference.spp), \(.reference.seconds | round) | "
        + "\(.reference.noise_thin | f), \(.reference.noise_dense | f) | "
        + "\(if $s.thin.pixels > 0 then ($s.thin.relative_rmse | f) else "–" end), \(if $s.dense.pixels > 0 then ($s.dense.relative_rmse | f) else "–" end) | "
        + "\(if $s.thin.pixels > 0 then ($s.thin.model_rmse | f) else "–" end), \(if $s.dense.pixels > 0 then ($s.dense.model_rmse | f) else "–" end) | "
        + "\(if $x == null then "–" else (if $x.thin.pixels > 0 then ($x.thin.relative_rmse | f) else "–" end) + ", " + (if $x.dense.pixels > 0 then ($x.dense.relative_rmse | f) else "–" end) end) | "
        + "\(if .best_interactive then "\(.best_interactive.name) (\(.best_interactive.relative_rmse | f), \(.best_interactive.speedup | round))" else "none" end) | "
        + "xi \(.best_xi) |"' "$r"
  done
}

if [ "${1:-}" = "--summary" ]; then
  summary "${2:?--summary needs the output folder}"
  exit 0
fi
OUT=${1:-validate_all}
SECONDS_REF=${2:-200}
mkdir -p "$OUT"
for s in default fig11_dawn fig5_rainbow fog_clear fig9_storm_sky fig10_storm_nosky fig4_glory; do
  echo "== $s $(date +%T), load $(cut -d' ' -f1-3 /proc/loadavg)"
  xvfb-run -a "$S" validate --scene "datasets/scenes/$s.json" --width 96 --height 72 --spp 100000000 \
    --seconds "$SECONDS_REF" --block 2 --quiet --out "$OUT/$s"
done
for pair in "fig13_low_albedo default" "fog_glow fog_clear" "haze_sun fog_clear"; do
  set -- $pair
  echo "== $1 (the reference of $2) $(date +%T), load $(cut -d' ' -f1-3 /proc/loadavg)"
  xvfb-run -a "$S" validate --scene "datasets/scenes/$1.json" --width 96 --height 72 --ref "$OUT/$2/reference.exr" \
    --block 2 --quiet --out "$OUT/$1"
done
summary "$OUT"
