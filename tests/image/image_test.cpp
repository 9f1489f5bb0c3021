// The in-memory image (surfgrad/image/image.h): sample layout (channels
// interleaved, bottom row first), the RGBA accessors, degenerate sizes, and
// an Image handed to the writer lands in the file top row first.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <vector>

#include "cli.h"
#include "surfgrad/image/image.h"
#include "surfgrad/image/image_write.h"
#include "surfgrad/base/io.h"

namespace sg::image {
namespace {

namespace fs = std::filesystem;

TEST(ImageType, LayoutIsRowMajorBottomRowFirstChannelsInterleaved) {
    Image img(3, 2, 2, 7.0f);
    EXPECT_EQ(img.samples.size(), 12u);
    EXPECT_EQ(img.texelCount(), 6u);
    EXPECT_FALSE(img.empty());
    EXPECT_FALSE(img.isFloat);
    for (float v : img.samples) EXPECT_EQ(v, 7.0f);
    img.at(2, 1, 1) = 5.0f; // the last texel's last channel
    EXPECT_EQ(img.samples.back(), 5.0f);
    img.at(1, 0, 0) = 3.0f;
    EXPECT_EQ(img.samples[2], 3.0f);
    EXPECT_EQ(img.index(1, 1), 4u);
}

TEST(ImageType, RgbaAccessOfFourChannelImages) {
    Image img(2, 2, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
    EXPECT_EQ(img.channels, 4);
    ASSERT_EQ(img.samples.size(), 16u);
    EXPECT_EQ(img.rgba(1, 1), glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
    img.setRgba(0, 1, glm::vec4(1, 2, 3, 4));
    EXPECT_EQ(img.rgba(img.index(0, 1)), glm::vec4(1, 2, 3, 4));
    EXPECT_EQ(img.at(0, 1, 2), 3.0f);
    EXPECT_EQ(img.samples[8], 1.0f); // texel 2 = (0, 1)
    img.setRgba(size_t(3), glm::vec4(9.0f));
    EXPECT_EQ(img.at(1, 1, 3), 9.0f);
}

TEST(ImageType, DegenerateSizesHoldNoSamples) {
    const Image none;
    EXPECT_EQ(none.width, 0);
    EXPECT_EQ(none.channels, 0);
    EXPECT_TRUE(none.empty());
    EXPECT_TRUE(Image(0, 5, 3).empty());
    EXPECT_TRUE(Image(5, 0, 3).empty());
    EXPECT_TRUE(Image(5, 5, 0).empty());
    EXPECT_EQ(Image(5, 0, 3).texelCount(), 0u);
    const FloatPixels view = floatPixels(none);
    EXPECT_EQ(view.samples, nullptr);
}

TEST(ImageType, WrittenTopRowFirst) {
    const fs::path dir = sg::test::processScratchDir("surfgrad_image_type");
    fs::create_directories(dir);
    Image img(2, 3, 1);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 2; ++x) img.at(x, y, 0) = float(10 * y + x);
    const fs::path p = dir / "rows.exr";
    writeImageFile(p, img, {});
    auto in = OIIO::ImageInput::open(p.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    std::vector<float> raw(6);
    ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, raw.data()));
    EXPECT_EQ(raw, (std::vector<float>{20, 21, 10, 11, 0, 1})); // file rows: top first
    EXPECT_THROW(writeImageFile(dir / "empty.exr", Image(), {}), io::InputError);
}

} // namespace
} // namespace sg::image
