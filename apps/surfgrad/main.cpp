// surfgrad command-line entry point: parses the command line (CLI11) and
// runs one subcommand. Every failure ends with a one-line message naming
// what failed and a non-zero exit status; no partial outputs are left.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "commands.h"
#include "surfgrad/bump.h"

#ifndef SURFGRAD_VERSION
#define SURFGRAD_VERSION "0.0.0"
#endif

int main(int argc, char** argv) {
    CLI::App app{"surfgrad: surface-gradient bump mapping on subdivision meshes"};
    app.set_version_flag("--version", std::string("surfgrad ") + SURFGRAD_VERSION +
                                          " (shader library v" +
                                          std::to_string(sg::kBumpLibraryVersion) + ")");
    app.require_subcommand(1);
    int status = 0;
    sg::cli::addEvalCommand(app, status);
    sg::cli::addSelftestCommand(app, status);
    sg::cli::addRenderCommands(app, status);
    CLI::App* meshGroup =
        sg::cli::addMeshCommands(app, status); // more mesh subcommands attach here
    sg::cli::addMeshTangentsCommand(*meshGroup, status);
    sg::cli::addFeaturesCommands(app, status);
    sg::cli::addNormalmapCommands(app, status);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        std::fflush(stdout);
        std::fprintf(stderr, "surfgrad: error: %s\n", e.what());
        return 1;
    }
    return status;
}
