// The tables of bench_accuracy_cost, one function each (docs/accuracy-cost.md
// describes the method of each and shows a run), and their registry: the one
// place a table is added. A new table is a source file defining its
// function (table_<name>.cpp: CMake picks it up) and ONE line in
// registeredTables() below; `--table NAME`, `--list`, bench/run (which
// rewrites the table's region of docs/accuracy-cost.md and plots it) and the
// page test (every registered table has its marked region on the page) all
// read this list. Each function creates the GL objects it needs in the
// context main() made current and prints its table(s) with Table::print
// (which also writes the plot data when Options::plotDataDir is set).
#pragma once

#include <vector>

#include "common.h"

namespace study {

struct TableEntry {
    const char* name;  // --table NAME; the page marker <!-- bench/run:table:NAME -->
    const char* title; // one line, for --list and progress output
    void (*run)(const Options&);
};

void tableFrames(const Options& o);      // 1: tangent frame source
void tableSubdivision(const Options& o); // 2: subdivision level
void tableBlend(const Options& o);       // 3: blend method
void tableFeatures(const Options& o);    // 4: feature-curve mode
void tableDerivatives(const Options& o); // 5: derivative method
void tablePrecision(const Options& o);   // 6: precision
void tableTriplanar(const Options& o);   // 7: triplanar method
void tableAntialias(const Options& o);   // 8: bump antialiasing
void tableParallax(const Options& o);    // 9: parallax and POM
void tableFeatureAa(const Options& o);   // 10: feature curves antialiased
void tableAdaptive(const Options& o);    // 11: adaptive patches vs uniform refinement
void tableStability(const Options& o);   // 12: numerical stability
void tableBake(const Options& o);        // 13: baking surface

// In page order. Register a table here, one line.
inline const std::vector<TableEntry>& registeredTables() {
    static const std::vector<TableEntry> tables = {
        {"frames", "1. tangent frame source", tableFrames},
        {"subdiv", "2. subdivision level", tableSubdivision},
        {"blend", "3. blend method", tableBlend},
        {"features", "4. feature-curve mode", tableFeatures},
        {"deriv", "5. derivative method", tableDerivatives},
        {"precision", "6. precision", tablePrecision},
        {"triplanar", "7. triplanar method", tableTriplanar},
        {"antialias", "8. bump antialiasing", tableAntialias},
        {"parallax", "9. parallax and POM", tableParallax},
        {"feature-aa", "10. feature curves antialiased", tableFeatureAa},
        {"adaptive", "11. adaptive patches vs uniform refinement", tableAdaptive},
        {"stability", "12. numerical stability of hard cases", tableStability},
        {"bake", "13. baking onto the limit surface vs the refined mesh", tableBake},
    };
    return tables;
}

} // namespace study
