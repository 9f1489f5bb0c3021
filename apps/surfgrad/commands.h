// Subcommands of build/bin/surfgrad. Each module registers its own
// subcommands; a subcommand's callback stores its exit status in `status`.
// Errors are reported by throwing sg::cli::CliError (or any std::exception):
// main prints "surfgrad: error: <message>" and exits 1.
#pragma once

#include <stdexcept>
#include <string>

namespace CLI {
class App;
}

namespace sg::cli {

struct CliError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

void addEvalCommand(CLI::App& app, int& status);
void addSelftestCommand(CLI::App& app, int& status);
// `surfgrad render`, `shader`, `view` (cmd_render.cpp, apps/render).
void addRenderCommands(CLI::App& app, int& status);
void addFeaturesCommands(CLI::App& app, int& status);
// `surfgrad normalmap ...` (cmd_normalmap.cpp, apps/normalmap).
void addNormalmapCommands(CLI::App& app, int& status);

// `surfgrad mesh ...` (cmd_mesh.cpp): adds the `mesh` group with info,
// subdivide and morph, and returns the group so other files can attach more
// `mesh` subcommands: in main.cpp,
//   CLI::App* mesh = addMeshCommands(app, status);
//   addMeshTangentsCommand(*mesh, status);   // cmd_mesh_tangents.cpp
CLI::App* addMeshCommands(CLI::App& app, int& status);
// `surfgrad mesh tangents ...` (cmd_mesh_tangents.cpp), attached to the mesh group.
void addMeshTangentsCommand(CLI::App& mesh, int& status);
// `--max-memory SIZE` (CLI11 size syntax: 12G, 800MiB, bytes) into `bytes`,
// for every command that subdivides (SubdivisionSettings::memoryBudget;
// 0: the default budget). kMaxMemoryHint: how refusals name the option.
inline constexpr const char* kMaxMemoryHint = "--max-memory SIZE";
void addMaxMemoryOption(CLI::App* cmd, uint64_t& bytes);
// Sets the mesh group's description from the subcommands attached to it
// (main.cpp calls it after the last one).
void describeMeshGroup(CLI::App& mesh);

} // namespace sg::cli
