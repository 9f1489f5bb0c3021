// surfgrad command-line entry point: parses the command line (CLI11) and
// runs one subcommand. Every failure ends with a one-line message naming
// what failed and a non-zero exit status; no partial outputs are left.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <new>
#include <string>

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
    sg::cli::describeMeshGroup(*meshGroup);
    sg::cli::addFeaturesCommands(app, status);
    sg::cli::addNormalmapCommands(app, status);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::bad_alloc&) {
        // Loaders check declared sizes against limits and the texture
        // budget before they allocate, and name the input when memory runs
        // out all the same; this is the last line for anything else.
        std::string args;
        for (int i = 1; i < argc; ++i) args += std::string(i > 1 ? " " : "") + argv[i];
        std::fflush(stdout);
        std::fprintf(stderr,
                     "surfgrad: error: out of memory (std::bad_alloc) running `surfgrad %s`: an "
                     "input declares more data than this machine can hold\n",
                     args.c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fflush(stdout);
        std::fprintf(stderr, "surfgrad: error: %s\n", e.what());
        return 1;
    }
    return status;
}
