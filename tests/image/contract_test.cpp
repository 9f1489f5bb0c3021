// The documented preconditions of the image writer (contract checks,
// surfgrad/base/contract.h): each violation aborts with "contract violated" in a
// checked build. Callers build these from their own images; untrusted
// input never reaches them.
#include <vector>

#include "contract_death.h"
#include "surfgrad/image/image.h"
#include "surfgrad/image/image_write.h"

namespace {

using namespace sg::image;
using ContractDeath = sg::test::ContractDeath;

TEST_F(ContractDeath, WriterNeedsSamplesAndMatchingNames) {
    const std::vector<float> px(4, 0.5f);
    WriteOptions names;
    names.channelNames = {"a", "b"};
    SG_EXPECT_CONTRACT_DEATH(writeImageFile("x.exr", {nullptr, 2, 2, 1}, {}), "samples to write");
    SG_EXPECT_CONTRACT_DEATH(writeImageFile("x.exr", {px.data(), 2, 2, 1}, names),
                             "one channel name per channel");
    WriteOptions alpha;
    alpha.alphaChannel = 1;
    SG_EXPECT_CONTRACT_DEATH(writeImageFile("x.exr", {px.data(), 2, 2, 1}, alpha),
                             "alphaChannel is -1 or one of the channels");
    WriteOptions empty;
    empty.attributes = {{"f", std::vector<float>{}}};
    SG_EXPECT_CONTRACT_DEATH(writeImageFile("x.exr", {px.data(), 2, 2, 1}, empty),
                             "at least one float");
}

TEST_F(ContractDeath, MipChainIsTheWholeRoundDownChain) {
    const std::vector<float> px(16, 0.5f);
    const FloatPixels l0{px.data(), 4, 2, 1}, l1{px.data(), 2, 1, 1}, l2{px.data(), 1, 1, 1};
    const FloatPixels wrong{px.data(), 2, 2, 1}, twoChannels{px.data(), 2, 1, 2};
    SG_EXPECT_CONTRACT_DEATH(writeMipChainFile("x.exr", {}, {}), "a MIP chain has a level 0");
    SG_EXPECT_CONTRACT_DEATH(writeMipChainFile("x.exr", {l0, wrong, l2}, {}),
                             "each level halves the previous one");
    SG_EXPECT_CONTRACT_DEATH(writeMipChainFile("x.exr", {l0, l1}, {}),
                             "the chain ends with a 1x1 level");
    SG_EXPECT_CONTRACT_DEATH(writeMipChainFile("x.exr", {l0, twoChannels, l2}, {}),
                             "every level has level 0's channels");
}

TEST_F(ContractDeath, ImageSizesAndSampleCount) {
    SG_EXPECT_CONTRACT_DEATH(Image(-1, 2, 1), "an image's size and channels are >= 0");
    SG_EXPECT_CONTRACT_DEATH(Image(2, 2, -4), "an image's size and channels are >= 0");
    Image truncated(2, 2, 3);
    truncated.samples.pop_back();
    SG_EXPECT_CONTRACT_DEATH(floatPixels(truncated), "Image::samples has width");
}

} // namespace
