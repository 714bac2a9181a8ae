#!/usr/bin/env bash
# `--tolerance default` against the default fit, per table in testdata/ (README: The fewest
# control points within a default tolerance): the default fit's count, max error and held-out
# max; the default tolerance T (0.5 % of the beam); the count `--tolerance default` keeps,
# whether it reached T, what its referee kept (and on which basis), its max error, held-out
# max, validity findings and plain fits tried. Errors in mm (the tables are in metres).
#
#   tools/tolerance_default_table.sh                  # every table; about 1 min
#   tools/tolerance_default_table.sh testdata/matlab_wpb.csv ...
#
# Prints a Markdown table. Needs jq. Deterministic: no timing.
source "$(dirname "${BASH_SOURCE[0]}")/speed_common.sh"
echo "| table | default count | max | held-out max | T | \`--tolerance default\` | T reached | referee kept | max | held-out max | findings | fits |"
echo "|---|---|--:|--:|--:|---|---|---|--:|--:|--:|--:|"
for t in "${tables[@]}"; do
  name=$(basename "$t" .csv)
  "$bin" fit "$t" $(opts "$t") -o "$out/d" >/dev/null 2>&1
  "$bin" fit "$t" $(opts "$t") --tolerance default -o "$out/t" >/dev/null 2>&1
  # A table without a beam (or a held-out error) has no search (or figure): a dash.
  jq -r --arg n "$name" --slurpfile d "$out/d/report.json" '
    def mm: if . == null then "-" else (. * 1e4 | round / 10 | tostring) end;
    def count: map(tostring) | join("x");
    .tolerance_search as $s | $d[0] as $d |
    [ $n, ($d.surface.control_points | count), ($d.error.max | mm), ($d.error.held_out.max | mm),
      ($s.tolerance | mm), (.surface.control_points | count),
      (if $s == null then "-" elif $s.kept_default_count then "no valid plain fit: default count kept"
       elif $s.reached then "yes" else "no: closest valid" end),
      (if $s.referee == null then "-"
       else (if $s.referee.chose_default_count then "default count" else "count found" end)
            + " (" + ($s.referee.basis | sub("_"; "-")) + ")" end),
      (.error.max | mm), (.error.held_out.max | mm), (.validity | length | tostring),
      ($s.fits // "-" | tostring) ]
    | "| " + join(" | ") + " |"' "$out/t/report.json"
done
