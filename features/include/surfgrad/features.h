// Umbrella header of the features module (surfgrad_features, features/).
// Feature-curve networks and their bake into feature maps: normal-map features
// that stay sharp at any magnification (Parilov et al. 2005, 2008). The
// runtime evaluator's math is shaders/sg/features/. Links bump, image and
// below.
//
// Includes every public header of the module:
//   surfgrad/features/curves.h        feature-curve networks: segments, JSON/SVG/font input
//   surfgrad/features/feature_maps.h  feature maps: the bake, their files, CPU evaluation
#pragma once

#include "surfgrad/features/curves.h"
#include "surfgrad/features/feature_maps.h"
