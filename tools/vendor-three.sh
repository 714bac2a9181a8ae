#!/usr/bin/env bash
# Rebuild crates/view/assets/three/three.min.js, the three.js bundle inlined into the 3-D viewer
# (crates/view/src/viewer/), from the npm registry, and check it against the sha256 recorded in
# crates/view/assets/three/README.md.
#
# The bundle is made by esbuild from the npm package `three` (both versions pinned below):
# only what the viewer uses (the entry point below) is bundled, minified, as one IIFE that
# defines the global `THREE`. The same versions give the same bytes.
#
#   tools/vendor-three.sh           rebuild and check the sha256 (fails if it differs)
#   tools/vendor-three.sh --update  rebuild and rewrite the sha256 in the README
#
# Needs node and npm (and the npm registry the first time).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

THREE_VERSION=0.187.0
ESBUILD_VERSION=0.28.2
out=crates/view/assets/three/three.min.js
readme=crates/view/assets/three/README.md

update=0
case "${1:-}" in
    "") ;;
    --update) update=1 ;;
    *) echo "usage: $0 [--update]" >&2; exit 2 ;;
esac

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

cat >"$work/package.json" <<JSON
{ "name": "hullskin-vendor-three", "version": "0.0.0", "private": true,
  "dependencies": { "three": "$THREE_VERSION", "esbuild": "$ESBUILD_VERSION" } }
JSON

# Every name the viewer's JavaScript (crates/view/src/viewer/viewer.js) takes from THREE.
cat >"$work/entry.js" <<'JS'
export {
    Box3,
    BufferAttribute,
    BufferGeometry,
    Color,
    DoubleSide,
    Float32BufferAttribute,
    Group,
    LineBasicMaterial,
    LineSegments,
    Mesh,
    PerspectiveCamera,
    Points,
    Scene,
    ShaderMaterial,
    Vector3,
    WebGLRenderer,
} from "three";
export { OrbitControls } from "three/addons/controls/OrbitControls.js";
JS

echo "==> npm install three@$THREE_VERSION esbuild@$ESBUILD_VERSION" >&2
(cd "$work" && npm install --no-audit --no-fund --loglevel=error >&2)
installed="$(node -p "require('$work/node_modules/three/package.json').version")"
[ "$installed" = "$THREE_VERSION" ] || { echo "got three $installed, wanted $THREE_VERSION" >&2; exit 1; }

echo "==> esbuild: one minified IIFE defining the global THREE" >&2
"$work/node_modules/.bin/esbuild" "$work/entry.js" --bundle --minify --format=iife --global-name=THREE \
    --target=es2020 --legal-comments=inline --charset=utf8 --log-level=warning --outfile="$work/three.min.js"

cp "$work/node_modules/three/LICENSE" crates/view/assets/three/LICENSE
sum="$(sha256sum "$work/three.min.js" | cut -d' ' -f1)"
if [ "$update" = 1 ]; then
    cp "$work/three.min.js" "$out"
    sed -i "s/^sha256: .*/sha256: $sum/" "$readme"
    echo "==> wrote $out ($(wc -c <"$out") bytes), sha256 $sum" >&2
else
    want="$(sed -n 's/^sha256: //p' "$readme")"
    if [ "$sum" != "$want" ]; then
        echo "rebuilt bundle sha256 $sum differs from $readme ($want)" >&2
        exit 1
    fi
    if ! cmp -s "$work/three.min.js" "$out"; then
        echo "$out differs from the rebuilt bundle (whose sha256 matches $readme): restore it" >&2
        exit 1
    fi
    echo "==> $out reproduced: sha256 $sum" >&2
fi
echo "$out"
