// dhdr's PNG writer (png_writer.h) against OpenImageIO's on the same pixels and spec, and
// its files read by readers apart from both: Python's zlib and struct, and pngcheck.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <cstdlib>
#include <dhdr/io/png_writer.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using dhdr::PngFileWriter;
using dhdr::PngWriteOptions;

namespace {

// A folder of this process's, removed when it ends.
struct Scratch {
    fs::path dir = fs::temp_directory_path() / ("dhdr_png_" + std::to_string(getpid()));
    Scratch() { fs::create_directories(dir); }
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

fs::path scratch() {
    static const Scratch s;
    return s.dir;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Random values; alpha 0, full and between, so that the division of associated alpha is
// exercised at its edges.
std::vector<unsigned char> randomPixels(const OIIO::ImageSpec& spec, unsigned seed) {
    std::vector<unsigned char> bytes(spec.image_bytes());
    std::mt19937 rng(seed);
    for (auto& b : bytes)
        b = static_cast<unsigned char>(rng());
    if (spec.alpha_channel < 0) return bytes;
    const size_t value = spec.format.size(), pixel = value * size_t(spec.nchannels);
    for (size_t p = 0; p < spec.image_pixels(); ++p) {
        unsigned char* a = &bytes[p * pixel + size_t(spec.alpha_channel) * value];
        const unsigned kind = rng() % 4;
        for (size_t i = 0; i < value; ++i)
            a[i] = kind == 0 ? 0 : kind == 1 ? 0xff : a[i];
    }
    return bytes;
}

OIIO::ImageSpec pngSpec(int w, int h, int channels, OIIO::TypeDesc type) {
    OIIO::ImageSpec spec(w, h, channels, type);
    spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("Software", "test_png_writer");
    spec.attribute("dhdr:note", "a tEXt chunk");
    spec.attribute("png:filter", 8); // libpng's PNG_FILTER_NONE
    return spec;
}

void writeOiio(const fs::path& path, const OIIO::ImageSpec& spec, const void* pixels) {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out && out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(spec.format, pixels));
    ASSERT_TRUE(out->close());
}

// Through PngFileWriter, the rows handed over in uneven strips.
void writeDhdr(const fs::path& path, const OIIO::ImageSpec& spec, const unsigned char* pixels,
               int nthreads, bool whole = false) {
    PngFileWriter png(path.string());
    PngWriteOptions options;
    options.nthreads = nthreads;
    options.whole = whole;
    ASSERT_TRUE(png.open(spec, options)) << png.geterror();
    const size_t row = spec.scanline_bytes();
    int y = 0, step = 1;
    while (y < spec.height) {
        const int end = std::min(spec.height, y + step);
        ASSERT_TRUE(png.writeRows(y, end, pixels + size_t(y) * row)) << png.geterror();
        y = end;
        step = step * 3 + 1;
    }
    ASSERT_TRUE(png.commit()) << png.geterror();
}

std::vector<unsigned char> decoded(const fs::path& path, OIIO::TypeDesc type) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    // As stored: no association of alpha on the way in.
    in.reset();
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    in = OIIO::ImageInput::open(path.string(), &config);
    std::vector<unsigned char> pixels(in->spec().image_bytes());
    EXPECT_TRUE(in->read_image(0, 0, 0, -1, type, pixels.data()));
    return pixels;
}

std::string beforeFirstIdat(const std::string& file) {
    // Up to the first IDAT's length field.
    return file.substr(0, file.find("IDAT") - 4);
}

int runPython(const std::string& script, const fs::path& png) {
    const fs::path py = scratch() / "check.py";
    std::ofstream(py) << script;
    return std::system(("/usr/bin/python3 " + py.string() + " " + png.string()).c_str());
}

// Chunks framed and their CRCs right, the IDATs one zlib stream (its Adler-32 checked by
// zlib), every row filter type 0 and of the width IHDR says.
const char* kPythonCheck = R"(
import struct, sys, zlib
data = open(sys.argv[1], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n'
at, idat, types = 8, b'', []
while at < len(data):
    n, = struct.unpack('>I', data[at:at + 4]); kind = data[at + 4:at + 8]
    body = data[at + 8:at + 8 + n]; crc, = struct.unpack('>I', data[at + 8 + n:at + 12 + n])
    assert zlib.crc32(kind + body) == crc, kind
    types.append(kind)
    if kind == b'IHDR': w, h, depth, colour = struct.unpack('>IIBB', body[:10])
    if kind == b'IDAT': idat += body
    at += 12 + n
assert types[0] == b'IHDR' and types[-1] == b'IEND', types
raw = zlib.decompress(idat)
channels = {0: 1, 4: 2, 2: 3, 6: 4}[colour]
row = 1 + w * channels * depth // 8
assert len(raw) == row * h, (len(raw), row * h)
assert all(raw[y * row] == 0 for y in range(h))
)";

struct Case {
    int w, h, channels;
    OIIO::TypeDesc type;
    bool unassociated = false; // "oiio:UnassociatedAlpha": alpha stored as given
};

} // namespace

TEST(PngWriter, GivesOpenImageIOsChunksAndPixels) {
    const Case cases[] = {{1, 1, 4, OIIO::TypeDesc::UINT8},
                          {1, 1, 1, OIIO::TypeDesc::UINT16},
                          {7, 3, 3, OIIO::TypeDesc::UINT8},
                          {33, 65, 2, OIIO::TypeDesc::UINT8},
                          {31, 17, 4, OIIO::TypeDesc::UINT16},
                          {301, 211, 1, OIIO::TypeDesc::UINT8},
                          // Rows of 32 KiB: several groups of rows, each deflated apart.
                          {4099, 101, 4, OIIO::TypeDesc::UINT16},
                          {9, 5, 4, OIIO::TypeDesc::UINT8, true}};
    unsigned seed = 1;
    for (const Case& c : cases) {
        SCOPED_TRACE(std::to_string(c.w) + "x" + std::to_string(c.h) + "x" +
                     std::to_string(c.channels) + " " + c.type.c_str());
        OIIO::ImageSpec spec = pngSpec(c.w, c.h, c.channels, c.type);
        if (c.unassociated) spec.attribute("oiio:UnassociatedAlpha", 1);
        const std::vector<unsigned char> pixels = randomPixels(spec, seed++);
        const fs::path ref = scratch() / "oiio.png", one = scratch() / "one.png",
                       three = scratch() / "three.png", whole = scratch() / "whole.png";
        writeOiio(ref, spec, pixels.data());
        writeDhdr(one, spec, pixels.data(), 1);
        writeDhdr(three, spec, pixels.data(), 3);
        EXPECT_EQ(slurp(one), slurp(three)) << "the bytes depend on the number of threads";
        EXPECT_EQ(beforeFirstIdat(slurp(one)), beforeFirstIdat(slurp(ref)));
        writeDhdr(whole, spec, pixels.data(), 2, true);
        EXPECT_EQ(beforeFirstIdat(slurp(whole)), beforeFirstIdat(slurp(ref)));
        for (const fs::path& ours : {one, whole}) {
            EXPECT_EQ(decoded(ours, c.type), decoded(ref, c.type)) << ours;
            EXPECT_EQ(runPython(kPythonCheck, ours), 0) << ours;
            if (fs::exists("/usr/bin/pngcheck"))
                EXPECT_EQ(std::system(("/usr/bin/pngcheck -q " + ours.string()).c_str()), 0);
        }
    }
}

TEST(PngWriter, LeavesNothingBehindWhenNotCommitted) {
    const OIIO::ImageSpec spec = pngSpec(5, 4, 3, OIIO::TypeDesc::UINT8);
    const std::vector<unsigned char> pixels = randomPixels(spec, 7);
    const fs::path path = scratch() / "partial.png";
    {
        PngFileWriter png(path.string());
        ASSERT_TRUE(png.open(spec, {}));
        ASSERT_TRUE(png.writeRows(0, 2, pixels.data()));
        EXPECT_FALSE(png.writeRows(3, 4, pixels.data())) << "rows skipped";
        EXPECT_NE(png.geterror().find(path.string()), std::string::npos) << png.geterror();
        EXPECT_FALSE(png.commit());
        EXPECT_NE(png.geterror().find("rows missing"), std::string::npos) << png.geterror();
    }
    for (const auto& e : fs::directory_iterator(scratch()))
        EXPECT_EQ(e.path().filename().string().find("partial"), std::string::npos) << e.path();
}

TEST(PngWriter, NamesAnOutputItCannotWrite) {
    const OIIO::ImageSpec spec = pngSpec(5, 4, 3, OIIO::TypeDesc::UINT8);
    const std::string path = (scratch() / "no such folder" / "out.png").string();
    PngFileWriter png(path);
    EXPECT_FALSE(png.open(spec, {}));
    EXPECT_EQ(png.geterror().rfind(path + ": cannot write", 0), 0u) << png.geterror();
}

TEST(PngWriter, LeavesToOpenImageIOWhatItDoesNotWrite) {
    EXPECT_FALSE(PngFileWriter::handles(OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::FLOAT)));
    EXPECT_FALSE(PngFileWriter::handles(OIIO::ImageSpec(4, 4, 5, OIIO::TypeDesc::UINT8)));
    OIIO::ImageSpec filtered(4, 4, 3, OIIO::TypeDesc::UINT8);
    filtered.attribute("png:filter", 0x10); // libpng's PNG_FILTER_SUB
    EXPECT_FALSE(PngFileWriter::handles(filtered));
    OIIO::ImageSpec gamma(4, 4, 4, OIIO::TypeDesc::UINT8);
    gamma.attribute("oiio:ColorSpace", "Gamma2.2"); // alpha divided out in floats there
    EXPECT_FALSE(PngFileWriter::handles(gamma));
    // libpng's own choice of filters (undithered output) is libpng's to make.
    EXPECT_FALSE(PngFileWriter::handles(OIIO::ImageSpec(4, 4, 4, OIIO::TypeDesc::UINT16)));
    OIIO::ImageSpec unfiltered(4, 4, 4, OIIO::TypeDesc::UINT16);
    unfiltered.attribute("png:filter", 8);
    EXPECT_TRUE(PngFileWriter::handles(unfiltered));
}
