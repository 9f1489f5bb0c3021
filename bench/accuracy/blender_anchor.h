// Table 13's anchor (docs/accuracy-cost.md, section 13): Blender's Cycles
// baker run headless on the same high mesh and the cage refined to a
// triangle mesh, through blender_bake.py (beside this file), so its maps can
// be drawn by the renderer and measured like the project's own bakes.
#pragma once

#include <filesystem>
#include <string>

#include <glm/glm.hpp>

#include "surfgrad/normalmap/operations.h"

namespace study {

// The Blender executable: $SURFGRAD_BLENDER when set, else `blender` on
// PATH; empty when there is none (the table then says so and has no
// Blender rows).
std::string findBlender();

struct BlenderBake {
    sg::normalmap::ScalarField height; // object units along LOW's normal, row 0 at v = 0
    sg::normalmap::DerivField slopes;  // tangent-space slopes in LOW's MikkTSpace frames
    double bakeMs = 0;                 // the four bake calls (normal, 2 positions, normal)
    double normalMs = 0;               // the tangent-space normal bake alone
    double processMs = 0;              // the whole blender process, start-up and reading
    std::string version;               // Blender's version string
};

// Bakes `high` onto `low`'s UV set 0 at size x size texels. Rays start at
// `low` pushed out by `extrusion` along its normal and run inwards up to
// 2 x extrusion (Cycles' "Selected to Active" cage), margin `padTexels`.
// Temporary files go to `dir`. Throws std::runtime_error naming the step
// when Blender fails or its output is not the expected size.
BlenderBake blenderBake(const std::string& blender, const std::filesystem::path& low,
                        const std::filesystem::path& high, const std::filesystem::path& dir,
                        int size, float extrusion, int padTexels);

} // namespace study
