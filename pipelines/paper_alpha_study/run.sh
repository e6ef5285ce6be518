#!/usr/bin/env bash
# Reruns the seed paper's experiment (section 6, Figures 4 and 5): the dam break with alpha = 0.5 and
# with the explicit scheme, D(t) of eq. (70) between the two and Q(t) = |(1/M) sum m v| of each.
# Usage: pipelines/paper_alpha_study/run.sh [OUT_DIR] [T_END] [THREADS]
#   OUT_DIR defaults to runs/paper_alpha_study, T_END to 1.0 s (the paper's span), THREADS to 1.
# Needs build/release/bin/varsph (or $VARSPH) and pvpython (numpy, matplotlib) for the figures.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
VARSPH="${VARSPH:-$ROOT/build/release/bin/varsph}"
OUT="${1:-$ROOT/runs/paper_alpha_study}"
TEND="${2:-1.0}"
THREADS="${3:-1}"
mkdir -p "$OUT"
"$VARSPH" run "$HERE/scene.json" -o "$OUT/implicit_alpha0.5" --overwrite --quiet --threads "$THREADS" \
  --set time.end="$TEND" &
"$VARSPH" run "$HERE/scene.json" -o "$OUT/explicit" --overwrite --quiet --threads "$THREADS" \
  --set time.end="$TEND" --set integrator.type='"verlet"' --set integrator.alpha=1 &
wait
"$VARSPH" compare "$OUT/implicit_alpha0.5" "$OUT/explicit" -o "$OUT/deviation" --overwrite
PY="${PYTHON:-pvpython}"
"$PY" "$HERE/plot.py" "$OUT"
echo "figures: $OUT/fig4_deviation.png $OUT/fig5_momentum.png; table: $OUT/summary.csv"
