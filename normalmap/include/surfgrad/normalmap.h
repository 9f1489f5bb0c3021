// Umbrella header of the normalmap module (surfgrad_normalmap, normalmap/).
// The height-field-correct normal-map operations on images (Loviscach 2008)
// next to the naive ones they replace: encodings, Poisson integration,
// LEAN/Toksvig MIP chains, object space through a mesh's frames. No GL: links
// bump, mesh, image and base.
//
// Includes every public header of the module:
//   surfgrad/normalmap/operations.h  grids, encodings, the operations and their naive twins
#pragma once

#include "surfgrad/normalmap/operations.h"
