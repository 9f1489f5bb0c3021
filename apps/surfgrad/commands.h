// Subcommands of build/bin/surfgrad. Each module registers its own
// subcommands; a subcommand's callback stores its exit status in `status`.
// Errors are reported by throwing: sg::cli::CliError for a command line
// that is wrong (main prints "surfgrad: error: <message>" and a pointer to
// the subcommand's --help, exit kExitUsage, as for CLI11's own parse
// errors); sg::io::InputError or any other std::exception for bad input
// or a failure (main prints "surfgrad: error: <message>", exit
// kExitFailure).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "surfgrad/mesh/mesh_io.h"

namespace CLI {
class App;
}

namespace sg::cli {

// Exit statuses of every subcommand (also printed by --help).
inline constexpr int kExitFailure = 1; // bad input (file, scene, mesh, ...) or a failure
inline constexpr int kExitUsage = 2;   // the command line: unknown, missing or invalid option
inline constexpr const char* kExitStatusHelp =
    "Exit status: 0 success; 1 bad input (a malformed or invalid file, scene or mesh; the "
    "message names the file, the element and the reason) or another failure; 2 a wrong "
    "command line (unknown, missing or invalid option or value).";

// The command line is wrong (an option's value, a combination of options,
// an option that does not fit the input given): exit kExitUsage.
struct CliError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

void addEvalCommand(CLI::App& app, int& status);
void addSelftestCommand(CLI::App& app, int& status);
// `surfgrad render`, `shader`, `view` (cmd_render.cpp, render).
void addRenderCommands(CLI::App& app, int& status);
void addFeaturesCommands(CLI::App& app, int& status);
// `surfgrad normalmap ...` (cmd_normalmap.cpp, normalmap).
void addNormalmapCommands(CLI::App& app, int& status);
// `surfgrad bake HIGH CAGE ...` (cmd_bake.cpp, bake).
void addBakeCommand(CLI::App& app, int& status);

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
// `--threads N` (1..1024; default: all cores) into `threads` (0 when not
// given), for every command whose work runs on several cores
// (surfgrad/base/threads.h).
void addThreadsOption(CLI::App* cmd, int& threads);
// Caps every TBB loop of the command at `threads` for as long as the
// returned object lives; 0: no cap (a null pointer).
std::unique_ptr<tbb::global_control> limitThreads(int threads);
// The glTF material of a mesh command's input, for its glTF output
// (WriteOptions::material; texture paths are rewritten relative to the
// output): the material of the file's first primitive that has one, with a
// note when the merged mesh had several (one mesh, one material) or when
// `gltfOutput` is false (OBJ/PLY outputs keep no material). Other formats:
// none.
std::optional<sg::mesh::Material> inputMaterial(const std::string& file, bool gltfOutput,
                                                std::vector<std::string>& notes);
// Sets the mesh group's description from the subcommands attached to it
// (main.cpp calls it after the last one).
void describeMeshGroup(CLI::App& mesh);

} // namespace sg::cli
