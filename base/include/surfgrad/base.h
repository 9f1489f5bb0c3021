// Umbrella header of the base module (surfgrad_base, base/).
// The error policy and the conventions every other module shares: one error
// type for untrusted input and atomic file output, contract checks of caller
// bugs, the thread-count convention of parallel jobs, scratch buffers of long
// jobs. Links nothing of ours.
//
// Includes every public header of the module:
//   surfgrad/base/contract.h        contract checks of caller bugs: SG_EXPECTS, SG_ASSERT, ...
//   surfgrad/base/io.h              sg::io::InputError, reading files, atomic writes
//   surfgrad/base/scratch_buffer.h  scratch vectors of long jobs (huge pages, no zero fill)
//   surfgrad/base/threads.h         how many threads a parallel job runs on (TBB)
#pragma once

#include "surfgrad/base/contract.h"
#include "surfgrad/base/io.h"
#include "surfgrad/base/scratch_buffer.h"
#include "surfgrad/base/threads.h"
