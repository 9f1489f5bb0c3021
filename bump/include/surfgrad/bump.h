// Umbrella header of the bump module (surfgrad_bump, bump/).
// The shader math of shaders/sg compiled as C++: the surface-gradient
// framework (Mikkelsen 2019), the derivative-space edits (Loviscach 2008), the
// patch bases of tessellation, and the evaluation table of every shared
// function. No I/O. Links shaders and base.
//
// Includes every public header of the module:
//   surfgrad/bump/core.h          the surface-gradient core compiled for the CPU (sg::glsl)
//   surfgrad/bump/patch_basis.h   the patch math of GPU tessellation compiled for the CPU
//   surfgrad/bump/record.h        kernel records: fields, widths and slots (SG_REC_FIELDS)
//   surfgrad/bump/eval_kernels.h  the evaluation table: kernels, layouts, parity inputs
//   surfgrad/bump/eval_line.h     the text format of `surfgrad eval`
#pragma once

#include "surfgrad/bump/core.h"
#include "surfgrad/bump/eval_kernels.h"
#include "surfgrad/bump/eval_line.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/bump/record.h"
