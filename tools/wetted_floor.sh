#!/usr/bin/env bash
# Issue 11's wetted-surface floor, per table in testdata/: the wetted surface S of the default
# fit and of `--method lm` within 2 % of the interpolation's (which passes through every
# offset), at a draft of 0.6 of the height of the interpolation's control net above its
# lowest control point.
#
#   tools/wetted_floor.sh                    # every table; about 2 min
#   tools/wetted_floor.sh testdata/matlab_trawler.csv ...
#
# Prints a Markdown table: S of interp, of the default fit and of LM, their differences from
# interp's in %, `yes` when within 2 %; then how many tables hold (both). Needs jq. Deterministic: no timing.
source "$(dirname "${BASH_SOURCE[0]}")/speed_common.sh"
wetted() { "$bin" hydrostatics "$1" --draft "$2" --json "${@:3}" 2>/dev/null | jq '.rows[0].s'; }

echo "| table | draft | interp S | default S | diff % | within 2 % | LM S | diff % | within 2 % |"
echo "|---|--:|--:|--:|--:|:-:|--:|--:|:-:|"
for t in "${tables[@]}"; do
  name=$(basename "$t" .csv)
  "$bin" fit "$t" $(opts "$t") --method interp --held-out 0 -o "$out/i" >/dev/null 2>&1
  draft=$(jq '[.control_points[][2]] | (min + 0.6 * (max - min))' "$out/i/surface.json")
  si=$(wetted "$out/i/surface.json" "$draft")
  sd=$(wetted "$t" "$draft" $(opts "$t"))
  "$bin" fit "$t" $(opts "$t") --method lm --held-out 0 -o "$out/l" >/dev/null 2>&1
  sl=$(wetted "$out/l/surface.json" "$draft")
  awk -v n="$name" -v d="$draft" -v i="$si" -v a="$sd" -v l="$sl" \
    'function pct(x) { return 100 * (x - i) / i }
     function ok(x) { return (pct(x) <= 2 && pct(x) >= -2) ? "yes" : "**no**" }
     BEGIN { printf "| %s | %.3f | %.2f | %.2f | %+.2f | %s | %.2f | %+.2f | %s |\n", n, d, i, a, pct(a), ok(a), l, pct(l), ok(l) }'
done > "$out/rows"
tally "$out/rows"
