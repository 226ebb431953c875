// What the tools share under apps/common: reading EXR bands on several threads and writing an
// output in strips, against OpenImageIO's own whole-image read and write.
#include "../apps/common/banded_read.h"
#include "../apps/common/tool.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <unistd.h>

namespace fs = std::filesystem;
using dhdr::app::readBanded;
using OIIO::ImageBuf;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

class AppCommon : public ::testing::Test {
protected:
    void SetUp() override {
        char pattern[] = "/tmp/dhdr_app_XXXXXX";
        dir = mkdtemp(pattern);
    }
    void TearDown() override { fs::remove_all(dir); }
    std::string path(const std::string& name) const { return (dir / name).string(); }

    // 150 rows (three bands and a part) of values that differ in every pixel and channel.
    std::string writeExr(const std::string& name, const std::string& compression,
                         const std::vector<TypeDesc>& formats) {
        ImageSpec spec(67, 150, int(formats.size()), TypeDesc::FLOAT);
        spec.channelformats = formats;
        spec.attribute("compression", compression);
        spec.attribute("dhdr:note", "kept");
        ImageBuf img(spec);
        for (int y = 0; y < 150; ++y)
            for (int x = 0; x < 67; ++x)
                for (int c = 0; c < spec.nchannels; ++c)
                    static_cast<float*>(img.pixeladdr(x, y))[c] =
                        float(x) * 0.25f - float(y) * 0.125f + float(c) * 3.0f;
        EXPECT_TRUE(img.write(path(name)));
        return path(name);
    }

    fs::path dir;
};

void expectSamePixels(const ImageBuf& a, const ImageBuf& b) {
    ASSERT_EQ(a.roi(), b.roi());
    ASSERT_EQ(a.nchannels(), b.nchannels());
    ASSERT_EQ(a.spec().format, TypeDesc::FLOAT);
    ASSERT_EQ(b.spec().format, TypeDesc::FLOAT);
    EXPECT_EQ(std::memcmp(a.localpixels(), b.localpixels(), a.spec().image_bytes()), 0);
}

TEST_F(AppCommon, BandedReadEqualsImageBufRead) {
    const TypeDesc H = TypeDesc::HALF, F = TypeDesc::FLOAT;
    for (const auto& [compression, formats] :
         std::vector<std::pair<std::string, std::vector<TypeDesc>>>{
             {"zip", {H, H, H, H}},
             {"dwab", {H, H, H}},
             {"piz", {F, F, F}},
             {"zip", {H, F, TypeDesc::UINT32}}}) {
        const std::string file = writeExr("in.exr", compression, formats);
        ImageBuf reference(file);
        ASSERT_TRUE(reference.read(0, 0, true, TypeDesc::FLOAT));
        // A uint channel holds integers (object ids), which OIIO's conversion would scale
        // to [0, 1]: the reference is its integer value, read by ImageInput as uint.
        for (int c = 0; c < int(formats.size()); ++c) {
            if (formats[size_t(c)] != TypeDesc::UINT32) continue;
            auto in = OIIO::ImageInput::open(file);
            std::vector<std::uint32_t> ids(size_t(67 * 150));
            ASSERT_TRUE(in->read_image(0, 0, c, c + 1, TypeDesc::UINT32, ids.data()));
            for (int y = 0; y < 150; ++y)
                for (int x = 0; x < 67; ++x)
                    static_cast<float*>(reference.pixeladdr(x, y))[c] =
                        float(ids[size_t(y * 67 + x)]);
        }
        for (int threads : {1, 2, 3}) {
            ImageBuf banded;
            std::string error;
            ASSERT_TRUE(readBanded(file, banded, 0, 99, threads, error)) << error;
            expectSamePixels(banded, reference);
            EXPECT_EQ(banded.spec().get_string_attribute("dhdr:note"), "kept");
            EXPECT_EQ(banded.spec().channelnames, reference.spec().channelnames);
        }
        // A run of channels, into an image of that size already there (a sequence's next
        // frame): the same memory, the new pixels.
        ImageBuf subset;
        const int middle[2] = {1, 2};
        const ImageBuf expected = OIIO::ImageBufAlgo::channels(reference, 2, middle);
        std::string error;
        ASSERT_TRUE(readBanded(file, subset, 1, 3, 2, error)) << error;
        const void* memory = subset.localpixels();
        OIIO::ImageBufAlgo::zero(subset);
        ASSERT_TRUE(readBanded(file, subset, 1, 3, 2, error)) << error;
        EXPECT_EQ(subset.localpixels(), memory);
        expectSamePixels(subset, expected);
        EXPECT_EQ(subset.spec().channelnames, (std::vector<std::string>{"G", "B"}));
    }
}

TEST_F(AppCommon, BandedReadReportsATruncatedFile) {
    const std::string file = writeExr("whole.exr", "zip", {TypeDesc::HALF, TypeDesc::HALF});
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(path("cut.exr"), std::ios::binary)
        .write(bytes.data(), std::streamsize(bytes.size() * 2 / 3));
    ImageBuf img;
    std::string error;
    EXPECT_FALSE(readBanded(path("cut.exr"), img, 0, 2, 2, error));
    EXPECT_FALSE(error.empty());
    EXPECT_FALSE(img.initialized());
}

TEST_F(AppCommon, OtherFormatsAreReadWhole) {
    ImageBuf png(ImageSpec(5, 4, 3, TypeDesc::UINT8));
    const float grey[3] = {0.2f, 0.4f, 0.6f};
    OIIO::ImageBufAlgo::fill(png, grey);
    ASSERT_TRUE(png.write(path("in.png")));
    ImageBuf img;
    std::string error;
    ASSERT_TRUE(readBanded(path("in.png"), img, 0, 3, 2, error)) << error;
    EXPECT_EQ(img.spec().format, TypeDesc::FLOAT);
    EXPECT_NEAR(static_cast<const float*>(img.pixeladdr(4, 3))[2], 153.0f / 255.0f, 1e-6);
}

// The rows of a gradient in UINT8 strips, through AtomicOutput::writeStrips.
bool writeGradient(const dhdr::app::Tool& tool, const std::string& file, bool overlap,
                   int failAtRow = -1) {
    ImageSpec spec(40, 150, 3, TypeDesc::UINT8);
    dhdr::app::AtomicOutput out(tool, file);
    if (!out.open(spec, {TypeDesc::UINT8})) return false;
    const bool written =
        out.writeStrips(TypeDesc::UINT8, 64, overlap, [&](OIIO::ROI strip, void* pixels) {
            if (strip.ybegin <= failAtRow && failAtRow < strip.yend) return false;
            auto* p = static_cast<unsigned char*>(pixels);
            for (int y = strip.ybegin; y < strip.yend; ++y)
                for (int x = 0; x < 40; ++x)
                    for (int c = 0; c < 3; ++c)
                        *p++ = static_cast<unsigned char>((x + y + c) % 256);
            return true;
        });
    return written && out.commit();
}

TEST_F(AppCommon, StripsWrittenWhileTheNextIsComputedMakeTheWholeImage) {
    dhdr::app::CommandLine cl("test", "", "");
    const dhdr::app::Tool tool("test", cl);
    ASSERT_TRUE(writeGradient(tool, path("overlap.png"), true));
    ASSERT_TRUE(writeGradient(tool, path("serial.png"), false));
    for (const char* name : {"overlap.png", "serial.png"}) {
        ImageBuf img(path(name));
        ASSERT_TRUE(img.read(0, 0, true, TypeDesc::UINT8));
        ASSERT_EQ(img.spec().height, 150);
        for (int y : {0, 63, 64, 127, 128, 149})
            for (int x : {0, 39})
                EXPECT_EQ(static_cast<const unsigned char*>(img.pixeladdr(x, y))[1],
                          (x + y + 1) % 256)
                    << name << " " << x << "," << y;
    }
    // A strip that fails leaves no file, not even the temporary one.
    EXPECT_FALSE(writeGradient(tool, path("failed.png"), true, 100));
    EXPECT_FALSE(fs::exists(dir / "failed.png"));
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find("failed"), std::string::npos)
            << entry.path();
}

} // namespace
