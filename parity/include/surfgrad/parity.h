// Umbrella header of the parity module (surfgrad_parity, parity/).
// CPU/GPU parity of every shared shader function, for `surfgrad selftest` and
// tests/bump. Links bump, gl and below.
//
// Includes every public header of the module:
//   surfgrad/parity/check.h  inputs, both evaluations, tolerances and the comparison
#pragma once

#include "surfgrad/parity/check.h"
