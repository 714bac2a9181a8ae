#!/usr/bin/env bash
# Runs the fuzz targets one after the other (docs/fuzzing.md), each for SECONDS, in
# libFuzzer's fork mode with one job so that a crash, hang or out-of-memory is recorded in
# fuzz/artifacts/<target>/ and the run goes on. Logs go to fuzz/logs/<target>.log (ignored by
# git); the summary line per target gives the final coverage and when it last grew.
#
# Usage, from anywhere: fuzz/run_all.sh [SECONDS] [TARGET...]   (default 180 s, every target)
set -euo pipefail
cd "$(dirname "$0")"
secs=${1:-180}
shift || true
all=$(sed -n 's/^name = "\(.*\)"$/\1/p' Cargo.toml | grep -v '^hullskin-fuzz$')
targets=${*:-$all}

dict_of() {
  case $1 in
    read_json_table) echo json ;;
    surface_json) echo surface ;;
    read_iges) echo iges ;;
    read_step) echo step ;;
    mesh_stl | mesh_parse_slice) echo stl ;;
    mesh_obj) echo obj ;;
    mesh_vrml) echo vrml ;;
    drawing_dxf | drawing_digitize) echo dxf ;;
    drawing_svg) echo svg ;;
    *) echo csv ;;
  esac
}

[ -d corpus ] || python3 seed_corpora.py
mkdir -p logs
cargo +nightly fuzz build -s none
for t in $targets; do
  mkdir -p "corpus/$t" "artifacts/$t"
  log="logs/$t.log"
  # fork mode prints "#N: cov: C ft: F corp: K exec/s E oom/timeout/crash: a/b/c time: Ts".
  # The binary built above, run directly: `cargo fuzz run` would rebuild whenever the
  # library changed under it.
  "target/x86_64-unknown-linux-gnu/release/$t" -artifact_prefix="artifacts/$t/" "corpus/$t" \
    -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -max_total_time="$secs" -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 \
    -dict="dicts/$(dict_of "$t").dict" >"$log" 2>&1 || true
  grep -E '^#[0-9]+: cov:' "$log" | awk -v t="$t" '
    { for (i = 1; i <= NF; i++) { if ($i == "cov:") c = $(i + 1); if ($i == "ft:") f = $(i + 1);
        if ($i == "time:") { s = $(i + 1); sub(/s$/, "", s) } if ($i == "oom/timeout/crash:") k = $(i + 1) }
      if (c != last) { grew = s; last = c } }
    END { printf "%-22s cov %s ft %s, cov last grew at %ss of %ss, oom/timeout/crash %s\n", t, c, f, grew, s, k }'
done
