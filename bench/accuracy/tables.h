// The tables of bench_accuracy_cost, one function each (docs/accuracy-cost.md
// describes the method of each and shows a run). Each creates its own
// headless GL context where it needs one and prints its table.
#pragma once

#include "common.h"

namespace study {

void tableFrames(const Options& o);      // 1: tangent frame source
void tableSubdivision(const Options& o); // 2: subdivision level
void tableBlend(const Options& o);       // 3: blend method
void tableFeatures(const Options& o);    // 4: feature-curve mode
void tableDerivatives(const Options& o); // 5: derivative method
void tablePrecision(const Options& o);   // 6: precision

} // namespace study
