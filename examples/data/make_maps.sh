#!/bin/sh
# Regenerates the baked normal maps of examples/data/ from the repository's
# data/ (or $SURFGRAD_DATA_DIR) with oiiotool and examples/tools/height_to_normal.py. See README.md here.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
data=${SURFGRAD_DATA_DIR:-$here/../../data}
bake="python3 $here/../tools/height_to_normal.py"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Spot's colour texture as a height (dark patches raised: --invert), bevelled.
$bake "$data/meshes/spot/spot_texture.png" "$here/spot_normal.png" --size 512 --depth 5 --blur 5 --wrap clamp --invert
# The same height (luminance, resized, blurred, inverted) as an 8-bit map:
# the tessellated asset's displacement.
oiiotool "$data/meshes/spot/spot_texture.png" --ch R,G,B --chsum:weight=0.2126,0.7152,0.0722 \
    --resize 512x512 --blur 5x5 --invert -d uint8 -o "$here/spot_height.png"
# A tileable rock from the CC0 lava height map.
$bake "$data/textures/lava_height.png" "$here/rock_normal.png" --size 256 --depth 8
# A branding-iron decal: an "S" in a frame (DejaVu Serif Bold), burned in (--invert).
font=/usr/share/fonts/truetype/dejavu/DejaVuSerif-Bold.ttf
oiiotool --create 256x256 1 \
    --box:color=1:fill=0 24,24,231,231 --box:color=1:fill=0 25,25,230,230 \
    --box:color=1:fill=0 26,26,229,229 --box:color=1:fill=0 27,27,228,228 \
    --box:color=1:fill=0 28,28,227,227 \
    --text:x=128:y=192:size=190:font=$font:color=1:xalign=center "S" -o "$tmp/brand.png"
$bake "$tmp/brand.png" "$here/brand_normal.png" --depth 4 --blur 5 --wrap clamp --invert
