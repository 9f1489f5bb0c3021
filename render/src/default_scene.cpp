// The built-in scene `surfgrad render` draws without arguments. It uses only
// procedural meshes and textures (no files), and shows the framework's
// point: bump influences of every kind, each a surface gradient, added and
// resolved once (Mikkelsen 2019, section 2), then detail resolved on top
// (section 3):
//   - a torus: bricks on UV set 0 plus a tiling weave detail map on UV set 1
//     (two UV sets, both with per-pixel frames: listing 6), a scratches decal
//     (listing 15), then a post-resolve group of turbulence dents composited
//     with Gritz's x^k (section 4);
//   - a sphere: a bumps normal map edited in derivative space (Loviscach
//     2008: slope curve and scale, using the map's height channel) plus fBm
//     volume noise (listing 12);
//   - a ground: triplanar tiles in world space (listings 13, 14) and a
//     height map of bumps (scale-dependent, listings 8, 9).
// It is written in the scene schema (docs/scene.md) and parsed like a file.
#include "surfgrad/render.h"

namespace sg::render {

namespace {

const char* kDefaultSceneJson = R"JSON({
  "output": { "width": 960, "height": 540, "exposure": 1.1 },
  "camera": { "position": [0.0, 1.55, 4.2], "target": [0.0, 0.35, 0.0], "fov_deg": 38 },
  "ambient": [0.10, 0.11, 0.13],
  "lights": [
    { "type": "directional", "direction": [-0.55, -0.65, -0.52], "color": [1.0, 0.95, 0.88], "intensity": 3.2 },
    { "type": "point", "position": [2.2, 1.6, 2.0], "color": [0.55, 0.7, 1.0], "intensity": 4.0 }
  ],
  "materials": [
    {
      "name": "torus",
      "base_color": [0.72, 0.45, 0.32],
      "roughness": 0.42,
      "layers": [
        { "type": "uv_normal", "uv_set": 0, "strength": 1.0,
          "map": { "procedural": "bricks", "size": 512, "bump_height": 0.012 } },
        { "type": "uv_normal", "uv_set": 1, "strength": 0.6,
          "map": { "procedural": "weave", "size": 256, "bump_height": 0.01 } },
        { "type": "decal", "position": [0.0, 0.95, 0.55], "direction": [0.0, -0.3, -1.0],
          "size": [0.9, 0.9, 1.2], "strength": 1.5,
          "map": { "procedural": "scratches", "size": 512, "bump_height": 0.004 } },
        { "type": "post_resolve", "layers": [
          { "type": "noise", "noise": "turbulence", "amplitude": 0.004, "frequency": 9.0,
            "octaves": 5, "exponent": 3.0, "space": "object" }
        ] }
      ]
    },
    {
      "name": "sphere",
      "base_color": [0.35, 0.5, 0.62],
      "roughness": 0.3,
      "layers": [
        { "type": "uv_normal", "uv_set": 0, "strength": 1.0,
          "map": { "procedural": "bumps", "size": 512, "bump_height": 0.01 },
          "height": { "channel": "a", "scale": 1.0 },
          "modifiers": [ { "type": "curve", "boost": 4000.0, "center": 0.008 }, { "type": "scale", "alpha": 1.5 } ] },
        { "type": "noise", "noise": "fbm", "amplitude": 0.01, "frequency": 6.0, "octaves": 6, "space": "object" }
      ]
    },
    {
      "name": "ground",
      "base_color": [0.55, 0.55, 0.52],
      "roughness": 0.6,
      "layers": [
        { "type": "triplanar", "map": { "procedural": "tiles", "size": 512, "bump_height": 0.02 },
          "scale": 0.5, "sharpness": 4, "space": "world", "strength": 1.0 },
        { "type": "height", "map": { "procedural": "bumps", "output": "height", "size": 256 },
          "uv_set": 1, "scale": 0.004 }
      ]
    }
  ],
  "meshes": [
    { "name": "torus", "procedural": { "type": "torus", "size": 0.62, "minor_radius": 0.27, "segments": 160 },
      "transform": { "translate": [-0.55, 0.62, 0.0], "rotate_deg": [72, 0, 18] }, "material": "torus" },
    { "name": "sphere", "procedural": { "type": "sphere", "size": 0.5, "segments": 128 },
      "transform": { "translate": [0.95, 0.5, -0.35] }, "material": "sphere" },
    { "name": "ground", "procedural": { "type": "plane", "size": 8.0, "segments": 8 },
      "material": "ground" }
  ]
})JSON";

} // namespace

Scene defaultScene() {
    Scene s = parseScene(kDefaultSceneJson, "<built-in default scene>", ".");
    return s;
}

} // namespace sg::render
