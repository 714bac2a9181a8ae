# Sourced by the speed tables (tools/lm_speed.sh, tools/default_speed.sh) with the tables as
# arguments: builds the release binary, sets `bin`, a scratch folder `out` removed on exit,
# `tables` (the arguments, or every table in testdata/) and `best` (the least of the numbers
# on its input). BIN=path measures another build of hullskin (an older commit, for a baseline).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
cargo build --release -q -p hullskin
bin=${BIN:-${CARGO_TARGET_DIR:-target}/release/hullskin}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
if [ $# -gt 0 ]; then tables=("$@"); else tables=(testdata/*.csv); fi
best() { tr ' ' '\n' | grep -v '^$' | sort -g | head -1; }
