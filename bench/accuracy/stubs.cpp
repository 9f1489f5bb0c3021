#include "tables.h"
namespace study {


void tableFeatures(const Options&) {}

void tablePrecision(const Options&) {}
}
