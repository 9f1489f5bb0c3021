// Umbrella header of the render module (surfgrad_render, render/).
// The surfgrad renderer: scenes (JSON, validated), shader assembly with effects
// on demand, the OpenGL 4.5 renderer, the CPU reference renderer and image
// output. The bump math is the surface-gradient framework of Mikkelsen,
// "Surface Gradient Based Bump Mapping Framework" (2019); every layer is a
// function of shaders/sg/render/*.glsl that both renderers run (the GPU as
// GLSL, the CPU through surfgrad/render/render_shaders.h).
//
// Pipeline:
//   Scene scene = loadScene("scene.json");       // or defaultScene()
//   SceneAssets assets = loadAssets(scene);      // meshes, only textures layers use
//   GlRenderer gl;                               // needs a current GL 4.5 context
//   Image img = gl.render(scene, assets, view);  // or renderCpu(scene, assets, view)
//   writeImage("out.png", img, Aov::Color, scene.output.exposure);
//
// Spaces and conventions (the whole module):
//  - world space is right-handed, y up; a camera looks down its -z axis;
//  - shading happens in world space RELATIVE TO THE CAMERA (listing 16);
//  - texture coordinates have (0,0) at the lower-left image corner, t up;
//    images are flipped on load so texel row 0 is the bottom row;
//  - images (Image = sg::image::Image, RGBA) are stored bottom row first, as
//    OpenGL reads them back; writers flip them to the usual top-first order.
// Errors: invalid scenes and assets throw sg::io::InputError naming the file,
// the field path (e.g. "materials[0].layers[2].strength") and the reason; GL
// failures throw sg::gl::GlError.
//
// The API is split by stage; this header includes every public header of
// the module but one:
//   surfgrad/render/scene.h           schema types, parseScene, loadScene, defaultScene
//   surfgrad/render/layer_params.h    parameters of the built-in layer kinds
//   surfgrad/render/assets.h          SceneAssets, loadAssets, applyFrame, loadTexture
//   surfgrad/render/view.h            View, makeView, makeOrbitView
//   surfgrad/render/plan.h            MaterialPlan, planMaterial, assembleProgram
//   surfgrad/render/image.h           Image, Aov, writeImage, readImage, compareVectorImages
//   surfgrad/render/renderer.h        GlRenderer, renderCpu, CpuOptions
//   surfgrad/render/glsl_texture.h    GLSL samplers emulated in C++ (textureGrad, ...)
//   surfgrad/render/render_shaders.h  the layer library compiled for the CPU; NOT included
//                                     here: the whole shader library as C++ (sg::glsl),
//                                     for the CPU reference renderer and the tests only
#pragma once

#include "surfgrad/render/assets.h"
#include "surfgrad/render/glsl_texture.h"
#include "surfgrad/render/image.h"
#include "surfgrad/render/layer_params.h"
#include "surfgrad/render/plan.h"
#include "surfgrad/render/renderer.h"
#include "surfgrad/render/scene.h"
#include "surfgrad/render/view.h"
