#!/usr/bin/env bash
# Issue 11's fairness floor, per table in testdata/: the default fit (`hullskin fit T`) against
# the plain approximation at the same control points (`--fair 0 --envelope free --ctrl NU,NV`),
# by report.json's `fairness`: thin-plate energy, the largest |K| (Gaussian curvature) and the
# inflections of 21 stations and 10 waterlines. A column is `yes` when the default fit is no
# worse than the plain one by that figure. The last column lists the plain fit's validity
# findings (kinds): the floor's comparator is not held within the envelope and may fold.
#
#   tools/fairness_floor.sh                    # every table; about 30 s
#   tools/fairness_floor.sh testdata/matlab_trawler.csv ...
#
# Prints a Markdown table, then how many tables hold. Needs jq. Deterministic: no timing.
source "$(dirname "${BASH_SOURCE[0]}")/speed_common.sh"
fig() { jq -r "$2" "$1/report.json"; }
kmax='.fairness.gaussian | map(fabs) | max'
infl='.fairness.station_inflections + .fairness.waterline_inflections'

echo "| table | ctrl | plain energy | default energy | holds | plain max abs K | default max abs K | holds | plain inflections | default inflections | holds | plain findings |"
echo "|---|--:|--:|--:|:-:|--:|--:|:-:|--:|--:|:-:|---|"
for t in "${tables[@]}"; do
  name=$(basename "$t" .csv)
  "$bin" fit "$t" $(opts "$t") --held-out 0 -o "$out/d" >/dev/null 2>&1
  ctrl=$(fig "$out/d" '.surface.control_points | map(tostring) | join(",")')
  "$bin" fit "$t" $(opts "$t") --fair 0 --envelope free --held-out 0 --ctrl "$ctrl" -o "$out/p" >/dev/null 2>&1
  awk -v n="$name" -v c="${ctrl/,/x}" \
    -v pe="$(fig "$out/p" .fairness.thin_plate)" -v de="$(fig "$out/d" .fairness.thin_plate)" \
    -v pk="$(fig "$out/p" "$kmax")" -v dk="$(fig "$out/d" "$kmax")" \
    -v pi="$(fig "$out/p" "$infl")" -v di="$(fig "$out/d" "$infl")" \
    -v ps="$(fig "$out/p" .fairness.station_inflections)" -v ds="$(fig "$out/d" .fairness.station_inflections)" \
    -v pf="$(fig "$out/p" '[.validity[].kind] | unique | join(" ")')" \
    'function yes(d, p) { return d <= p ? "yes" : "**no**" }
     BEGIN { printf "| %s | %s | %.4g | %.4g | %s | %.4g | %.4g | %s | %d (%d st) | %d (%d st) | %s | %s |\n",
             n, c, pe, de, yes(de, pe), pk, dk, yes(dk, pk), pi, ps, di, ds, yes(di, pi), (pf == "" ? "none" : pf) }'
done > "$out/rows"
tally "$out/rows"
