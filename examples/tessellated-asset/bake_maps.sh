#!/bin/sh
# Bakes this example's displacement and normal maps with `surfgrad bake`
# from a high-resolution Spot: the limit surface at level 6 (1.5M
# triangles) displaced along its limit normal by 0.012 x
# ../data/spot_height.png, a stand-in for a sculpt. The bake puts both maps
# on the cage's limit surface, which is what the adaptive patches draw.
# Usage: examples/tessellated-asset/bake_maps.sh [path/to/surfgrad]
# (default build/bin/surfgrad). Needs python3 and oiiotool.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
surfgrad=${1:-$here/../../build/bin/surfgrad}
data=${SURFGRAD_DATA_DIR:-$here/../../data}
cage="$data/meshes/spot/spot_control_mesh.obj"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$surfgrad" mesh subdivide "$cage" --level 6 --limit -o "$tmp/spot_limit.obj"
python3 "$here/../tools/displace_mesh.py" "$tmp/spot_limit.obj" "$here/../data/spot_height.png" \
    "$tmp/spot_sculpt.obj" --scale 0.012
"$surfgrad" bake "$tmp/spot_sculpt.obj" "$cage" --size 512 --isolation 3 \
    --displacement "$here/../data/spot_baked_height.exr" --displacement-bits half \
    --normal "$here/../data/spot_baked_normal.png"
