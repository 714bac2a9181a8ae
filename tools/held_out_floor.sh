#!/usr/bin/env bash
# Issue 11's held-out floor, per table in testdata/: the default fit (`hullskin fit T`, which
# cross-validates with 4 folds) against the plain approximation at the same control points
# (`--fair 0 --envelope free --ctrl NU,NV`, cross-validated the same way), by report.json's
# `error.held_out.max`: the default fit's held-out max error no worse than the plain one's
# (`holds`). Also the max error at the offsets of both, and the validity findings (count and
# kinds) of the default fit and of the plain one (which the envelope hold does not correct: the
# comparator of every table where the default fit fails the floor has some). Errors in mm (the tables are in
# metres). With METHOD=lm (or another `--method`), that method's fit in place of the default
# fit (the floor names the default fit and `--method lm`); its refits are that method's too.
#
#   tools/held_out_floor.sh                    # every table; about 1 min
#   tools/held_out_floor.sh testdata/matlab_trawler.csv ...
#   METHOD=lm tools/held_out_floor.sh          # LM; about 2 min
#
# Prints a Markdown table, then how many tables hold. Needs jq. Deterministic: no timing.
source "$(dirname "${BASH_SOURCE[0]}")/speed_common.sh"
fig() { jq -r "$2" "$1/report.json"; }
# The fit under test: the default fit, or METHOD's.
label=${METHOD:-default}
method=()
[ -n "${METHOD:-}" ] && method=(--method "$METHOD")

echo "| table | ctrl | plain max | $label max | plain held-out max | $label held-out max | holds | $label findings | plain findings |"
echo "|---|--:|--:|--:|--:|--:|:-:|---|---|"
for t in "${tables[@]}"; do
  name=$(basename "$t" .csv)
  "$bin" fit "$t" $(opts "$t") "${method[@]}" -o "$out/d" >/dev/null 2>&1
  ctrl=$(fig "$out/d" '.surface.control_points | map(tostring) | join(",")')
  "$bin" fit "$t" $(opts "$t") --fair 0 --envelope free --ctrl "$ctrl" -o "$out/p" >/dev/null 2>&1
  awk -v n="$name" -v c="${ctrl/,/x}" \
    -v pm="$(fig "$out/p" .error.max)" -v dm="$(fig "$out/d" .error.max)" \
    -v ph="$(fig "$out/p" .error.held_out.max)" -v dh="$(fig "$out/d" .error.held_out.max)" \
    -v f="$(fig "$out/d" '.validity | length')" -v k="$(fig "$out/d" '[.validity[].kind] | unique | join(" ")')" \
    -v pf="$(fig "$out/p" '.validity | length')" -v pk="$(fig "$out/p" '[.validity[].kind] | unique | join(" ")')" \
    'function yes(d, p) { return d <= p ? "yes" : "**no**" }
     function found(f, k) { return f (f > 0 ? " (" k ")" : "") }
     BEGIN { printf "| %s | %s | %.1f | %.1f | %.1f | %.1f | %s | %s | %s |\n",
             n, c, 1e3 * pm, 1e3 * dm, 1e3 * ph, 1e3 * dh, yes(dh, ph), found(f, k), found(pf, pk) }'
done > "$out/rows"
tally "$out/rows"
