#!/usr/bin/env bash
# The default fit's cost against the plain approximation's, per table in testdata/ (issue 11:
# the default fit, cross-validation included, within 50x the plain approximation of the same
# table, measured in the same run).
#
#   tools/default_speed.sh                     # every table; about 1 min
#   tools/default_speed.sh testdata/matlab_yacht.csv ...
#   REPS=5 tools/default_speed.sh              # best of 5 default fits (6 plain) instead of 2 (3)
#
# For each table: the control points and offsets of the default fit; the seconds of the plain
# approximation (`--method approx --fair 0 --envelope free --held-out 0`: the least squares alone, the
# summary's `time`, i.e. report.json `seconds`, fit plus error measurement; best of REPS + 1,
# interleaved), of the default fit before its cross-validation (fairing search, envelope hold,
# alternatives, validity: report.json `held_out_referee.default_fit_seconds`, or `seconds` where
# it is not refereed; best of REPS) and of the whole default fit (`hullskin fit T`: that, the
# 4-fold cross-validation and the held-out referee, which cross-validates the plain
# approximation and any alternative it tries: `default_fit_seconds` + `default_held_out_seconds`
# + `held_out_referee.seconds`, or `seconds` + `error.held_out.seconds` where it is not
# refereed; best of REPS), and the ratios. Process start and file writing are left out of every
# column. Prints a Markdown table. Needs jq. Times depend on the machine and its load.
source "$(dirname "${BASH_SOURCE[0]}")/speed_common.sh"
reps=${REPS:-2}
# The default fit's whole cost, whichever surface was written (with its held-out referee: the
# default fit, its cross-validation and the referee's own), and its cost before the
# cross-validation (`fitted`).
secs() {
  jq 'if .held_out_referee then .held_out_referee | .default_fit_seconds + .default_held_out_seconds + .seconds
      else .seconds + (.error.held_out.seconds // 0) end' "$1/report.json"
}
fitted() { jq '.held_out_referee.default_fit_seconds // .seconds' "$1/report.json"; }

echo "| table | ctrl | m | plain ms | default before CV ms | ratio | default ms | ratio |"
echo "|---|--:|--:|--:|--:|--:|--:|--:|"
for t in "${tables[@]}"; do
  name=$(basename "$t" .csv)
  a="" h="" d=""
  for r in $(seq $((reps + 1))); do
    "$bin" fit "$t" $(opts "$t") --method approx --fair 0 --envelope free --held-out 0 -o "$out/a" >/dev/null 2>&1
    a="$a $(secs "$out/a")"
    if [ "$r" -le "$reps" ]; then
      "$bin" fit "$t" $(opts "$t") -o "$out/d" >/dev/null 2>&1
      h="$h $(fitted "$out/d")"
      d="$d $(secs "$out/d")"
    fi
  done
  a=$(echo "$a" | best)
  h=$(echo "$h" | best)
  d=$(echo "$d" | best)
  ctrl=$(jq -r '.surface.control_points | map(tostring) | join("x")' "$out/d/report.json")
  m=$(jq '.input.points' "$out/d/report.json")
  awk -v n="$name" -v c="$ctrl" -v m="$m" -v a="$a" -v h="$h" -v d="$d" \
    'BEGIN { printf "| %s | %s | %d | %.1f | %.0f | %.1f | %.0f | %.1f |\n", n, c, m, 1000 * a, 1000 * h, h / a, 1000 * d, d / a }'
done
