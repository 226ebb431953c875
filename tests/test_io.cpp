// The io library the tools stream their frames through: reading EXR bands on several threads,
// writing an output atomically, and the strip pipeline, against OpenImageIO's own
// whole-image read and write and against the whole frame processed at once.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <dhdr/io/banded_read.h>
#include <dhdr/io/image_output.h>
#include <dhdr/io/strip_pipeline.h>
#include <dhdr/io/strip_reader.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <limits>
#include <tuple>
#include <unistd.h>

namespace fs = std::filesystem;
using dhdr::readBanded;
using OIIO::ImageBuf;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

class IO : public ::testing::Test {
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

TEST_F(IO, BandedReadEqualsImageBufRead) {
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

TEST_F(IO, BandedReadReportsATruncatedFile) {
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

TEST_F(IO, OtherFormatsAreReadWhole) {
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

// The rows of a gradient in UINT8 strips, through a StripPipeline without inputs; the
// process fails at `failAtRow`.
bool writeGradient(const std::string& file, bool overlap, int failAtRow = -1) {
    ImageSpec spec(40, 150, 3, TypeDesc::UINT8);
    dhdr::ImageFileOutput out(file);
    if (!out.open(spec, {TypeDesc::UINT8})) return false;
    dhdr::StripPipelineParams params;
    params.writeBehind = overlap;
    dhdr::StripPipeline pipeline(OIIO::get_roi(spec), params);
    pipeline.setOutput(out);
    const bool written = pipeline.run([&](dhdr::StripContext& strip) {
        if (strip.rows.ybegin <= failAtRow && failAtRow < strip.rows.yend) {
            strip.error = "failed on purpose";
            return false;
        }
        ImageSpec rows(40, strip.rows.height(), 3, TypeDesc::UINT8);
        rows.y = strip.rows.ybegin;
        strip.output->reset(rows);
        for (int y = strip.rows.ybegin; y < strip.rows.yend; ++y)
            for (int x = 0; x < 40; ++x)
                for (int c = 0; c < 3; ++c)
                    static_cast<unsigned char*>(strip.output->pixeladdr(x, y))[c] =
                        static_cast<unsigned char>((x + y + c) % 256);
        return true;
    });
    if (!written) {
        EXPECT_EQ(pipeline.error(), "failed on purpose");
    }
    return written && out.commit();
}

TEST_F(IO, StripsWrittenWhileTheNextIsComputedMakeTheWholeImage) {
    ASSERT_TRUE(writeGradient(path("overlap.png"), true));
    ASSERT_TRUE(writeGradient(path("serial.png"), false));
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
    EXPECT_FALSE(writeGradient(path("failed.png"), true, 100));
    EXPECT_FALSE(fs::exists(dir / "failed.png"));
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find("failed"), std::string::npos)
            << entry.path();
}

// A frame with non-finite values in its colour and a +Inf Z, for the pipeline's sanitizing.
std::string writeHostileFrame(const std::string& file, int width, int height) {
    ImageSpec spec(width, height, 4, TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    ImageBuf img(spec);
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float* p = static_cast<float*>(img.pixeladdr(x, y));
            for (int c = 0; c < 3; ++c)
                p[c] = float((x * 7 + y * 13 + c * 5) % 17) * 0.5f;
            p[3] = (x + y) % 5 == 0 ? inf : float(x + y);
            if ((x * 3 + y) % 23 == 0) p[0] = nan;
            if ((x + y * 5) % 29 == 0) p[1] = inf;
            if ((x * 11 + y) % 31 == 0) p[2] = -inf;
        }
    EXPECT_TRUE(img.write(file));
    return file;
}

// The rule of sanitize.h, written out: NaN and −Inf are 0, +Inf is 65504.
float sanitized(float v) {
    if (std::isnan(v) || v == -std::numeric_limits<float>::infinity()) return 0.0f;
    return std::isinf(v) ? 65504.0f : v;
}

// A vertical 3-tap filter of colour (its reach: one row, the halo), run through the pipeline
// in strips of `rows`, and written; Z is copied as it is.
// With `share`, a strip's shared rows are copied from the previous strip (counted in `reused`).
bool filterFrame(const std::string& in, const std::string& out, int rows, bool readAhead,
                 bool writeBehind, dhdr::NonFiniteCount& replaced, std::string& error, int halo = 1,
                 bool share = false, int* reused = nullptr) {
    dhdr::StripReader reader;
    if (!reader.open(in, 0, 0, 4, 2, error)) return false;
    const ImageSpec frame = reader.spec();
    dhdr::ImageFileOutput file(out);
    dhdr::StripPipelineParams params;
    params.rows = rows;
    params.halo = halo;
    params.shareHalo = share;
    params.readAhead = readAhead;
    params.writeBehind = writeBehind;
    dhdr::StripPipeline pipeline(OIIO::get_roi(frame), params);
    dhdr::StripInput input{[&](int y0, int y1, ImageBuf& strip, std::string& e) {
                               return reader.read(y0, y1, strip, e);
                           },
                           in,
                           {{0, 3}}};
    input.readReusing = [&](int y0, int y1, const ImageBuf& previous, ImageBuf& strip,
                            int& copiedEnd, std::string& e) {
        if (reused) ++*reused;
        return reader.read(y0, y1, strip, e, &previous, &copiedEnd);
    };
    pipeline.addInput(std::move(input));
    // Opened from the first processed strip.
    pipeline.setOutput(file, [&](const ImageBuf& first, std::string& e) {
        ImageSpec spec = first.spec();
        spec.y = frame.y;
        spec.height = frame.height;
        if (file.open(spec, {TypeDesc::FLOAT})) return true;
        e = file.geterror();
        return false;
    });
    const bool ok = pipeline.run([&](dhdr::StripContext& strip) {
        const ImageBuf& src = *strip.inputs[0];
        ImageSpec rowsSpec(frame.width, strip.rows.height(), 4, TypeDesc::FLOAT);
        rowsSpec.y = strip.rows.ybegin;
        rowsSpec.channelnames = frame.channelnames;
        strip.output->reset(rowsSpec);
        for (int y = strip.rows.ybegin; y < strip.rows.yend; ++y)
            for (int x = 0; x < frame.width; ++x) {
                float* q = static_cast<float*>(strip.output->pixeladdr(x, y));
                for (int c = 0; c < 3; ++c) {
                    float sum = 0.0f;
                    for (int dy : {-1, 0, 1}) {
                        const int yy = std::clamp(y + dy, 0, frame.height - 1);
                        sum += static_cast<const float*>(src.pixeladdr(x, yy))[c];
                    }
                    q[c] = sum / 3.0f;
                }
                q[3] = static_cast<const float*>(src.pixeladdr(x, y))[3];
            }
        return true;
    });
    if (!ok) {
        error = pipeline.error();
        return false;
    }
    replaced = pipeline.replaced()[0];
    if (file.commit()) return true;
    error = file.geterror();
    return false;
}

// Whatever the strips, the halo and the threads, the frame is the one filtered whole from the
// sanitized input (computed here from the file read by OpenImageIO), and the counts of
// replaced values are the file's own.
TEST_F(IO, StripPipelineGivesTheWholeFrameWhateverTheStrips) {
    const int width = 37, height = 101;
    const std::string in = writeHostileFrame(path("hostile.exr"), width, height);
    ImageBuf source(in);
    ASSERT_TRUE(source.read(0, 0, true, TypeDesc::FLOAT));
    long long nan = 0, positive = 0, negative = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = static_cast<const float*>(source.pixeladdr(x, y))[c];
                nan += std::isnan(v);
                positive += v == std::numeric_limits<float>::infinity();
                negative += v == -std::numeric_limits<float>::infinity();
            }
    ASSERT_GT(nan * positive * negative, 0);
    // Rows, read ahead, write behind, halo, shared halo rows copied (only when halo ≤ rows).
    for (const auto& [rows, readAhead, writeBehind, halo, share] :
         std::vector<std::tuple<int, bool, bool, int, bool>>{{1, false, false, 1, false},
                                                             {7, true, false, 1, false},
                                                             {64, true, true, 1, false},
                                                             {200, false, true, 1, false},
                                                             {1, true, false, 1, true},
                                                             {7, true, true, 3, true},
                                                             {16, false, false, 16, true},
                                                             {10, true, false, 4, true},
                                                             {3, true, false, 5, true}}) {
        const std::string name =
            std::to_string(rows) + "_" + std::to_string(halo) + (share ? "_shared" : "");
        SCOPED_TRACE("rows " + name);
        const std::string out = path("filtered" + name + ".exr");
        dhdr::NonFiniteCount replaced;
        std::string error;
        int reused = 0;
        ASSERT_TRUE(filterFrame(in, out, rows, readAhead, writeBehind, replaced, error, halo, share,
                                &reused))
            << error;
        // Every strip but the first copies its shared rows, unless the halo is taller than it.
        EXPECT_EQ(reused, share && halo <= rows ? (height + rows - 1) / rows - 1 : 0);
        EXPECT_EQ(replaced.nan, nan);
        EXPECT_EQ(replaced.positiveInf, positive);
        EXPECT_EQ(replaced.negativeInf, negative);
        ImageBuf result(out);
        ASSERT_TRUE(result.read(0, 0, true, TypeDesc::FLOAT));
        ASSERT_EQ(result.spec().height, height);
        int wrong = 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const float* q = static_cast<const float*>(result.pixeladdr(x, y));
                for (int c = 0; c < 3; ++c) {
                    float sum = 0.0f;
                    for (int dy : {-1, 0, 1}) {
                        const int yy = std::clamp(y + dy, 0, height - 1);
                        sum += sanitized(static_cast<const float*>(source.pixeladdr(x, yy))[c]);
                    }
                    wrong += q[c] != sum / 3.0f;
                }
                // Z is left out of the sanitizing, and the output keeps its +Inf (the
                // G-buffer contract's background).
                wrong += q[3] != static_cast<const float*>(source.pixeladdr(x, y))[3];
            }
        EXPECT_EQ(wrong, 0);
    }
}

// Rows read again with the previous read's buffer: those it holds are copied, the rest
// decoded, and the strip is the one a plain read gives, bit for bit; without an overlap, or
// from a buffer of other rows, nothing is copied.
TEST_F(IO, StripReaderCopiesTheRowsTheLastReadHeld) {
    const std::string in = writeHostileFrame(path("overlap.exr"), 23, 90);
    dhdr::StripReader reader;
    std::string error;
    ASSERT_TRUE(reader.open(in, 0, 0, 4, 2, error)) << error;
    auto same = [](const ImageBuf& a, const ImageBuf& b) {
        return a.roi() == b.roi() &&
               std::memcmp(a.localpixels(), b.localpixels(), size_t(a.spec().image_bytes())) == 0;
    };
    ImageBuf first, second, plain;
    ASSERT_TRUE(reader.read(10, 40, first, error)) << error;
    int copiedEnd = -1;
    ASSERT_TRUE(reader.read(30, 70, second, error, &first, &copiedEnd)) << error;
    EXPECT_EQ(copiedEnd, 40);
    ASSERT_TRUE(reader.read(30, 70, plain, error)) << error;
    EXPECT_TRUE(same(second, plain));
    // Clamped to the image: rows 80–89 of 90, all held by `second`'s successor.
    ImageBuf tail, tailPlain;
    ASSERT_TRUE(reader.read(60, 95, first, error)) << error;
    ASSERT_TRUE(reader.read(80, 120, tail, error, &first, &copiedEnd)) << error;
    EXPECT_EQ(copiedEnd, 90);
    ASSERT_TRUE(reader.read(80, 120, tailPlain, error)) << error;
    EXPECT_TRUE(same(tail, tailPlain));
    // No overlap at the strip's first row: decoded.
    ASSERT_TRUE(reader.read(0, 20, second, error, &plain, &copiedEnd)) << error;
    EXPECT_EQ(copiedEnd, 0);
    ASSERT_TRUE(reader.read(0, 20, tailPlain, error)) << error;
    EXPECT_TRUE(same(second, tailPlain));
}

// A file that cannot be read half way: the error names it, and nothing is left behind.
TEST_F(IO, StripPipelineStopsAtAReadErrorAndLeavesNoOutput) {
    const std::string whole = writeHostileFrame(path("whole.exr"), 64, 400);
    std::ifstream src(whole, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(src)), {});
    const std::string cut = path("cut.exr");
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
    for (const bool readAhead : {false, true}) {
        dhdr::NonFiniteCount replaced;
        std::string error;
        EXPECT_FALSE(filterFrame(cut, path("out.exr"), 16, readAhead, true, replaced, error));
        EXPECT_EQ(error.rfind(cut + ": cannot read: ", 0), 0u) << error;
        EXPECT_FALSE(fs::exists(path("out.exr")));
        for (const auto& entry : fs::directory_iterator(dir))
            EXPECT_EQ(entry.path().filename().string().find("out"), std::string::npos)
                << entry.path();
    }
}

// Every stage runs once a strip, in order, whatever overlaps: reads and writes each in
// sequence, and a process failure stops the frame with its message.
TEST(StripPipeline, StagesRunInOrderAndStopAtTheFirstFailure) {
    for (const bool overlap : {false, true}) {
        dhdr::StripPipelineParams params;
        params.rows = 10;
        params.readAhead = params.writeBehind = overlap;
        std::vector<float> progress;
        params.progress = [&](float f) { progress.push_back(f); };
        std::vector<int> read, processed, written;
        dhdr::StripStages stages;
        stages.read = [&](OIIO::ROI r, int slot, std::string&) {
            EXPECT_EQ(slot, (r.ybegin / 10) % 2);
            read.push_back(r.ybegin);
            return true;
        };
        stages.process = [&](OIIO::ROI r, int, std::string&) {
            processed.push_back(r.ybegin);
            return true;
        };
        stages.write = [&](OIIO::ROI r, int, std::string&) {
            written.push_back(r.ybegin);
            return true;
        };
        std::string error;
        ASSERT_TRUE(dhdr::runStrips(OIIO::ROI(0, 5, 0, 35), params, stages, error));
        const std::vector<int> all = {0, 10, 20, 30};
        EXPECT_EQ(read, all);
        EXPECT_EQ(processed, all);
        EXPECT_EQ(written, all);
        EXPECT_EQ(progress, (std::vector<float>{0.25f, 0.5f, 0.75f, 1.0f}));
        stages.process = [&](OIIO::ROI r, int, std::string& e) {
            if (r.ybegin < 20) return true;
            e = "stopped at 20";
            return false;
        };
        written.clear();
        EXPECT_FALSE(dhdr::runStrips(OIIO::ROI(0, 5, 0, 35), params, stages, error));
        EXPECT_EQ(error, "stopped at 20");
        EXPECT_EQ(written, (std::vector<int>{0, 10}));
    }
}

} // namespace
