# Sourced by the speed tables (tools/lm_speed.sh, tools/default_speed.sh) and the floor tables
# (tools/*_floor.sh) with the tables as arguments: builds the release binary, sets `bin`, a
# scratch folder `out` removed on exit, `tables` (the arguments, or every table in testdata/),
# `best` (the least of the numbers on its input) and `opts` (a table's own options). BIN=path
# measures another build of hullskin (an older commit, for a baseline).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
cargo build --release -q -p hullskin
bin=${BIN:-${CARGO_TARGET_DIR:-target}/release/hullskin}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# Every table of testdata/: the offset tables and sections, and the meshes (sliced at the default
# stations as `hullskin fit MESH` slices them; issue 11's floors name the DTC and DTMB 5415
# meshes; the FastShip designs in VRML are in shared/data too).
if [ $# -gt 0 ]; then tables=("$@"); else tables=(testdata/*.csv testdata/mesh/*.stl.gz testdata/mesh/*.wrl.gz); fi
# The options a table needs besides its path, for every command that reads it: the OpenFOAM
# Wigley mesh has x from -L/2 and z = 0 at the waterline, shifted to x from its aft end and z from
# its keel (hullskin's axes; the slice tests do the same); the FastShip container ship and
# dragger have z down (deck at z < 0), turned up by --axes (shared/data/fastship_sample_hulls).
opts() {
  case "$(basename "$1")" in
    wigley.stl.gz) echo "--shift 0.5,0,0.0625" ;;
    fastship_cont.wrl.gz | fastship_50dragger.wrl.gz) echo "--axes x,y,-z" ;;
  esac
}
best() { tr ' ' '\n' | grep -v '^$' | sort -g | head -1; }
# The floor tables' last line: how many rows (tables) hold, i.e. have no `**no**` in any column.
tally() {
  cat "$1"
  echo
  echo "Holds on $(grep -vc '[*][*]no[*][*]' "$1" || true) of $(wc -l < "$1") tables."
}
