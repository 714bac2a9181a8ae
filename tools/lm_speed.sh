#!/usr/bin/env bash
# LM's cost against the plain approximation's, per table in testdata/ (issue 11, item 5: LM
# within 15x the approximation of the same table, measured in the same run).
#
#   tools/lm_speed.sh                    # every table; about 1 min
#   BEFORE=/path/to/old/hullskin tools/lm_speed.sh   # adds the old binary's LM, same run
#   tools/lm_speed.sh testdata/matlab_yacht.csv ...  # some tables
#   REPS=4 tools/lm_speed.sh             # best of 4 LM runs (5 approximations) instead of 2 (3)
#
# For each table: weights d (full grid: the control points), offsets m, the time column of
# `hullskin fit` (fit plus error measurement, the summary's `time`) for the plain
# approximation (`--fair 0`; best of REPS + 1, interleaved with the LM runs), for `--method lm`
# (on the fair objective of `--fair auto`, the default, with its fallback to a sound
# approximation when LM's surface has a validity finding; best of REPS) and for `--method lm
# --fair 0` (the plain objective; best of REPS), all `--held-out 0`, the ratios to the
# approximation and LM's true RMS; with BEFORE, the old binary's LM (default and `--fair 0`, best
# of REPS each, interleaved with the others) and their ratios to the same approximation. Prints a
# Markdown table. Needs jq. Times depend on the machine and its load.
source "$(dirname "${BASH_SOURCE[0]}")/speed_common.sh"

# ms of the summary row printed by `hullskin fit` (the row under the header: `lm`, or `approx`
# when LM's surface was rejected for a sound approximation; the argument names the method
# asked for).
ms() { awk 'prev ~ /^method / { print $(NF - 1) } { prev = $0 }'; }

if [ -n "${BEFORE:-}" ]; then
  echo "| table | d | m | approx ms | LM ms | ratio | LM RMS mm | LM fair 0 ms | ratio | RMS mm | before: LM ms | ratio | RMS mm | before: LM fair 0 ms | ratio | RMS mm |"
  echo "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
else
  echo "| table | d | m | approx ms | LM ms | ratio | LM RMS mm | LM fair 0 ms | ratio | RMS mm |"
  echo "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
fi
for t in "${tables[@]}"; do
  name=$(basename "$t" .csv)
  a="" l="" z="" bl="" bz=""
  reps=${REPS:-2}
  for r in $(seq 1 $((reps + 1))); do
    a="$a $("$bin" fit "$t" $(opts "$t") --fair 0 --held-out 0 -o "$out/a" | ms approx)"
    if [ "$r" -le "$reps" ]; then
      l="$l $("$bin" fit "$t" $(opts "$t") --method lm --held-out 0 -o "$out/l" | ms lm)"
      z="$z $("$bin" fit "$t" $(opts "$t") --method lm --fair 0 --held-out 0 -o "$out/z" | ms lm)"
      if [ -n "${BEFORE:-}" ]; then
        bl="$bl $("$BEFORE" fit "$t" $(opts "$t") --method lm --held-out 0 -o "$out/bl" | ms lm)"
        bz="$bz $("$BEFORE" fit "$t" $(opts "$t") --method lm --fair 0 --held-out 0 -o "$out/bz" | ms lm)"
      fi
    fi
  done
  a=$(echo "$a" | best)
  l=$(echo "$l" | best)
  z=$(echo "$z" | best)
  d=$(jq '.surface.control_points[0] * .surface.control_points[1]' "$out/l/report.json")
  m=$(jq '.input.points' "$out/l/report.json")
  rms=$(jq '.error.rms * 1000' "$out/l/report.json")
  zrms=$(jq '.error.rms * 1000' "$out/z/report.json")
  row=$(awk -v n="$name" -v d="$d" -v m="$m" -v a="$a" -v l="$l" -v r="$rms" -v z="$z" -v zr="$zrms" \
    'BEGIN { printf "| %s | %d | %d | %.2f | %.1f | %.1f | %.4g | %.1f | %.1f | %.4g |", n, d, m, a, l, l / a, r, z, z / a, zr }')
  if [ -n "${BEFORE:-}" ]; then
    bl=$(echo "$bl" | best)
    bz=$(echo "$bz" | best)
    blrms=$(jq '.error.rms * 1000' "$out/bl/report.json")
    bzrms=$(jq '.error.rms * 1000' "$out/bz/report.json")
    row="$row$(awk -v a="$a" -v b="$bl" -v r="$blrms" -v z="$bz" -v zr="$bzrms" \
      'BEGIN { printf " %.1f | %.1f | %.4g | %.1f | %.1f | %.4g |", b, b / a, r, z, z / a, zr }')"
  fi
  echo "$row"
done
