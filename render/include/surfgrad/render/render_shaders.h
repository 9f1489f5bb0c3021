// The renderer's shader library compiled for the CPU: the bump layers,
// noise and shading of shaders/sg/render/*.glsl, on top of the
// surface-gradient core (surfgrad/bump/core.h) and the texture emulation
// (surfgrad/render/glsl_texture.h). The CPU reference renderer and the tests call
// these as sg::glsl::sgLayerUvNormal(...), etc.; the GPU compiles the same
// files. Contracts are documented in the .glsl files.
#pragma once

#include "surfgrad/bump/core.h"
#include "surfgrad/features/feature_maps.h" // the feature evaluator and its CPU samplers
#include "surfgrad/render/glsl_texture.h"

namespace sg::glsl {
#include "sg/render/common.glsl"
#include "sg/render/noise.glsl"
#include "sg/render/layer_uv_normal.glsl"
#include "sg/render/antialias.glsl"
#include "sg/render/slope_dist.glsl"
#include "sg/render/layer_uv_normal_aa.glsl"
#include "sg/render/layer_object_normal.glsl"
#include "sg/render/layer_height.glsl"
#include "sg/render/layer_parallax.glsl"
#include "sg/render/layer_deriv_map.glsl"
#include "sg/render/layer_triplanar.glsl"
#include "sg/render/layer_decal.glsl"
#include "sg/render/layer_triplanar_aa.glsl"
#include "sg/render/layer_decal_aa.glsl"
#include "sg/render/layer_noise.glsl"
#include "sg/render/layer_noise_aa.glsl"
#include "sg/render/deriv_mods.glsl"
#include "sg/render/layer_uv_normal_mods.glsl"
#include "sg/render/layer_deriv_map_mods.glsl"
#include "sg/render/layer_feature.glsl"
#include "sg/render/layer_feature_aa.glsl"
#include "sg/render/shading.glsl"
} // namespace sg::glsl
