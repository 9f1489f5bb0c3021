// Helpers of the example tests: read the images a built program wrote
// (programs run through tests/common/cli.h).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "cli.h"

namespace sg::examples_test {

namespace fs = std::filesystem;

using sg::test::CommandResult;
using sg::test::runCommand;
using sg::test::shellQuote;

// A fresh scratch directory for one test, inside the process's scratch
// folder (removed when the process exits).
inline fs::path scratchDir(const std::string& name) {
    fs::path d = sg::test::processScratchDir("surfgrad_examples") / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels; // top row first, `channels` floats per pixel
    float at(int x, int y, int c) const {
        return pixels[(size_t(y) * size_t(width) + size_t(x)) * size_t(channels) + size_t(c)];
    }
};

// Reads any OpenImageIO format as float (8-bit PNG values become v / 255).
// Returns an empty image (width 0) when the file cannot be read.
inline Image readImage(const fs::path& path) {
    Image img;
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return img;
    const OIIO::ImageSpec& spec = in->spec();
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    img.pixels.resize(size_t(img.width) * size_t(img.height) * size_t(img.channels));
    if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
        img.width = 0;
    in->close();
    return img;
}

} // namespace sg::examples_test
