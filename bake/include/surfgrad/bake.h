// Umbrella header of the bake module (surfgrad_bake, bake/).
// A high-resolution mesh baked onto a cage's limit surface (docs/bake.md):
// displacement and tangent- and object-space normal maps, through the adaptive
// patches and the shared patch bases, rays through Embree 3. Links normalmap
// and below.
//
// Includes every public header of the module:
//   surfgrad/bake/baker.h  BakeSettings, bake(), BakeResult
#pragma once

#include "surfgrad/bake/baker.h"
