#include "tables.h"
namespace study {
void tableSubdivision(const Options&) {}

void tableFeatures(const Options&) {}
void tableDerivatives(const Options&) {}
void tablePrecision(const Options&) {}
}
