// Umbrella header of the image module (surfgrad_image, image/).
// The one in-memory image (sg::image::Image), the one reader of untrusted
// image files (header scan and limits before any decoder allocates, band-by-
// band decoding) and the one writer of image files (PNG, OpenEXR, TIFF, TGA,
// atomically). Links base.
//
// Includes every public header of the module:
//   surfgrad/image/image.h         sg::image::Image: float samples, bottom row first
//   surfgrad/image/image_header.h  image headers read before any decoder sees a file
//   surfgrad/image/image_decode.h  decoding untrusted files into the smallest sample type
//   surfgrad/image/image_write.h   writing images and MIP chains, atomically
//   surfgrad/image/image_format.h  sample types, metadata values, lowerExtension
#pragma once

#include "surfgrad/image/image.h"
#include "surfgrad/image/image_decode.h"
#include "surfgrad/image/image_format.h"
#include "surfgrad/image/image_header.h"
#include "surfgrad/image/image_write.h"
