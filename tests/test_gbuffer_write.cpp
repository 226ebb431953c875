// G-buffer files written the fast way (flat through OpenEXR itself, deep samples packed a
// pixel at a time, any zip level, any thread count) hold the bits the old way wrote: every
// channel decoded by the other library than the one that wrote it (issue 47).
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <cstdlib>
#include <cstring>
#include <dhdr/deferred/gbuffer/deep_gbuffer.h>
#include <dhdr/deferred/gbuffer/gbuffer.h>
#include <dhdr/deferred/render/gbuffer_render.h>
#include <dhdr/deferred/scene/scene.h>
#include <dhdr/deferred/scene/scene_camera.h>
#include <dhdr/io/image_output.h>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <iterator>
#include <map>

using namespace dhdr;
namespace fs = std::filesystem;

namespace {

fs::path scratch() {
    const fs::path dir =
        fs::temp_directory_path() / ("dhdr_gbuffer_write_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

struct Rendered {
    Scene scene;
    OIIO::ImageSpec spec;
    OIIO::ImageBuf flat;
    DeepGBuffer deep;
};

// A scene's G-buffer at w × h, flat and deep, from its own camera.
void render(const std::string& name, int w, int h, Rendered& r) {
    std::string error;
    ASSERT_TRUE(loadScene(std::string(DHDR_TESTDATA) + "/" + name, r.scene, error)) << error;
    Camera camera;
    std::vector<std::string> notes, warnings;
    ASSERT_TRUE(
        chooseCamera(r.scene, name, CameraChoice{}, double(w) / h, camera, error, notes, warnings))
        << error;
    GBufferParams p;
    p.width = w;
    p.height = h;
    const GBufferRenderer renderer(r.scene, camera, p);
    ASSERT_TRUE(renderer.ok()) << renderer.error();
    r.spec = renderer.spec();
    // A fixed date, so that two files of the same pixels are the same bytes.
    r.spec.attribute("DateTime", "2026:12:07 12:00:00");
    ASSERT_TRUE(renderer.render(r.flat, {}, 0));
    ASSERT_TRUE(renderer.renderDeep(r.deep, {}, 0));
}

// Writes `r.flat` in strips of 16 rows, through OpenEXR itself or through OpenImageIO.
void writeFlat(const Rendered& r, const fs::path& path, bool throughOpenExr,
               const std::string& compression, int exrThreads) {
    OIIO::attribute("exr_threads", exrThreads);
    ImageOutputOptions options;
    options.software = "test";
    options.compression = compression;
    options.throughOpenExr = throughOpenExr;
    ImageFileOutput out(path.string(), options);
    ASSERT_TRUE(out.open(r.spec, gbuffer::channelFormats(r.spec.channelnames))) << out.geterror();
    EXPECT_EQ(out.writesThroughOpenExr(), throughOpenExr);
    for (int y = 0; y < r.spec.height; y += 16) {
        const OIIO::ROI rows(0, r.spec.width, y, std::min(y + 16, r.spec.height));
        ASSERT_TRUE(out.writeRows(r.flat, rows)) << out.geterror();
    }
    ASSERT_TRUE(out.commit()) << out.geterror();
}

// Each channel's bytes as OpenEXR's own InputFile decodes them, by name.
std::map<std::string, std::vector<char>> decodeWithOpenExr(const fs::path& path) {
    Imf::InputFile in(path.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    const size_t w = size_t(dw.max.x - dw.min.x + 1), h = size_t(dw.max.y - dw.min.y + 1);
    std::map<std::string, std::vector<char>> out;
    Imf::FrameBuffer fb;
    for (auto c = in.header().channels().begin(); c != in.header().channels().end(); ++c) {
        const size_t bytes = c.channel().type == Imf::HALF ? 2 : 4;
        std::vector<char>& plane = out[c.name()];
        plane.resize(w * h * bytes);
        fb.insert(c.name(), Imf::Slice(c.channel().type, plane.data(), bytes, bytes * w));
    }
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    return out;
}

// The same with OpenImageIO, each channel in its file type.
std::map<std::string, std::vector<char>> decodeWithOiio(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << OIIO::geterror();
    std::map<std::string, std::vector<char>> out;
    if (!in) return out;
    const OIIO::ImageSpec& s = in->spec();
    for (int c = 0; c < s.nchannels; ++c) {
        const OIIO::TypeDesc t = s.channelformat(c);
        std::vector<char>& plane = out[s.channelnames[size_t(c)]];
        plane.resize(s.image_pixels() * t.size());
        EXPECT_TRUE(in->read_image(0, 0, c, c + 1, t, plane.data())) << in->geterror();
    }
    return out;
}

// Every attribute of the header of `a` is in `b` with the same type and value (capDate
// aside), and the other way round.
void expectSameHeaders(const fs::path& a, const fs::path& b) {
    Imf::InputFile fa(a.c_str()), fb(b.c_str());
    auto names = [](const Imf::Header& h) {
        std::map<std::string, std::string> m;
        for (auto i = h.begin(); i != h.end(); ++i)
            m[i.name()] = i.attribute().typeName();
        return m;
    };
    EXPECT_EQ(names(fa.header()), names(fb.header()));
    auto sa = OIIO::ImageInput::open(a.string()), sb = OIIO::ImageInput::open(b.string());
    ASSERT_TRUE(sa && sb);
    for (const OIIO::ParamValue& p : sa->spec().extra_attribs) {
        const OIIO::ParamValue* q = sb->spec().find_attribute(p.name());
        ASSERT_TRUE(q) << p.name();
        EXPECT_EQ(p.type(), q->type()) << p.name();
        EXPECT_EQ(p.get_string(1000), q->get_string(1000)) << p.name();
    }
}

std::string bytesOf(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

bool leftovers(const fs::path& dir) {
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
    return false;
}

} // namespace

TEST(GBufferWrite, OpenExrWriterGivesOpenImageIOsBitsAndHeader) {
    Rendered r;
    render("shot.gltf", 173, 97, r); // textured, odd sizes: strips end mid line block
    const fs::path dir = scratch();
    for (const std::string compression : {"", "zip:1", "zips", "piz", "rle", "none"}) {
        SCOPED_TRACE("compression '" + compression + "'");
        const fs::path old = dir / "old.exr", fast = dir / "fast.exr";
        writeFlat(r, old, false, compression, 2);
        writeFlat(r, fast, true, compression, 2);
        expectSameHeaders(old, fast);
        // Each file decoded by the library that did not write it, against the other.
        const auto oldByExr = decodeWithOpenExr(old), fastByOiio = decodeWithOiio(fast);
        ASSERT_EQ(oldByExr.size(), size_t(r.spec.nchannels));
        ASSERT_EQ(fastByOiio.size(), oldByExr.size());
        for (const auto& [name, plane] : oldByExr)
            EXPECT_TRUE(fastByOiio.at(name) == plane) << name;
        EXPECT_TRUE(decodeWithOpenExr(fast) == decodeWithOiio(old));
    }
    fs::remove_all(dir);
}

TEST(GBufferWrite, FilesDoNotDependOnThreads) {
    Rendered r;
    render("cornell_box.gltf", 160, 120, r);
    const fs::path dir = scratch();
    for (const std::string compression : {"", "zip:1", "piz"}) {
        writeFlat(r, dir / "one.exr", true, compression, 1);
        writeFlat(r, dir / "four.exr", true, compression, 4);
        writeFlat(r, dir / "none.exr", true, compression, -1);
        EXPECT_EQ(bytesOf(dir / "one.exr"), bytesOf(dir / "four.exr")) << compression;
        EXPECT_EQ(bytesOf(dir / "one.exr"), bytesOf(dir / "none.exr")) << compression;
    }
    OIIO::attribute("exr_threads", 0);
    fs::remove_all(dir);
}

// OpenImageIO's own per-value fill of a deep strip: what toDeepData wrote before it filled
// through pointers.
void referenceDeepData(const DeepGBuffer& g, const std::vector<OIIO::TypeDesc>& formats,
                       OIIO::DeepData& out) {
    const int nch = g.spec.nchannels;
    const size_t npix = size_t(g.spec.width) * size_t(g.spec.height);
    out.init(int64_t(npix), nch, formats, g.spec.channelnames);
    std::vector<unsigned> counts(npix);
    for (size_t p = 0; p < npix; ++p)
        counts[p] = g.first[p + 1] - g.first[p];
    out.set_all_samples(counts);
    for (size_t p = 0; p < npix; ++p)
        for (unsigned s = 0; s < counts[p]; ++s) {
            const float* v = &g.values[(size_t(g.first[p]) + s) * size_t(nch)];
            for (int c = 0; c < nch; ++c) {
                if (formats[size_t(c)] == OIIO::TypeDesc::UINT)
                    out.set_deep_value(int64_t(p), c, int(s), std::uint32_t(std::max(v[c], 0.0f)));
                else
                    out.set_deep_value(int64_t(p), c, int(s), v[c]);
            }
        }
}

TEST(GBufferWrite, DeepSamplesKeepTheirBitsAtAnyThreadCount) {
    Rendered r;
    render("cornell_glass.gltf", 120, 90, r);
    bool layered = false; // the glass in front of the box: pixels of two samples or more
    for (size_t p = 0; p + 1 < r.deep.first.size(); ++p)
        layered = layered || r.deep.first[p + 1] - r.deep.first[p] > 1;
    ASSERT_TRUE(layered);
    const std::vector<OIIO::TypeDesc> formats = gbuffer::channelFormats(r.deep.spec.channelnames);
    OIIO::DeepData packed, reference;
    toDeepData(r.deep, 0, 90, packed, formats);
    referenceDeepData(r.deep, formats, reference);
    ASSERT_EQ(packed.pixels(), reference.pixels());
    for (int64_t p = 0; p < packed.pixels(); ++p) {
        ASSERT_EQ(packed.samples(p), reference.samples(p));
        if (packed.samples(p) > 0)
            ASSERT_EQ(0, std::memcmp(packed.data_ptr(p, 0, 0), reference.data_ptr(p, 0, 0),
                                     packed.samplesize() * size_t(packed.samples(p))))
                << "pixel " << p;
    }
    const fs::path dir = scratch();
    OIIO::ImageSpec spec = r.deep.spec;
    spec.channelformats = formats;
    spec.attribute("DateTime", "2026:12:07 12:00:00");
    for (const int threads : {1, 3}) {
        OIIO::attribute("exr_threads", threads);
        ImageOutputOptions options;
        options.compression = "zips:1";
        ImageFileOutput out((dir / ("deep" + std::to_string(threads) + ".exr")).string(), options);
        ASSERT_TRUE(out.openDeep(spec)) << out.geterror();
        for (int y = 0; y < 90; y += 32) {
            OIIO::DeepData rows;
            toDeepData(r.deep, y, std::min(y + 32, 90), rows, formats);
            ASSERT_TRUE(out.writeDeepRows(y, std::min(y + 32, 90), rows)) << out.geterror();
        }
        ASSERT_TRUE(out.commit()) << out.geterror();
    }
    OIIO::attribute("exr_threads", 0);
    EXPECT_EQ(bytesOf(dir / "deep1.exr"), bytesOf(dir / "deep3.exr"));
    // Decoded by OpenImageIO's deep reader (the file was written by OpenEXR's).
    auto in = OIIO::ImageInput::open((dir / "deep1.exr").string());
    ASSERT_TRUE(in) << OIIO::geterror();
    OIIO::DeepData read;
    ASSERT_TRUE(in->read_native_deep_scanlines(0, 0, 0, 90, 0, 0, spec.nchannels, read));
    ASSERT_EQ(read.pixels(), reference.pixels());
    for (int64_t p = 0; p < read.pixels(); ++p) {
        ASSERT_EQ(read.samples(p), reference.samples(p));
        for (int c = 0; c < spec.nchannels; ++c) {
            int rc = 0; // OpenImageIO orders a file's channels its own way
            while (rc < read.channels() && read.channelname(rc) != reference.channelname(c))
                ++rc;
            ASSERT_LT(rc, read.channels()) << reference.channelname(c);
            for (int s = 0; s < read.samples(p); ++s) {
                const size_t bytes = formats[size_t(c)].size();
                ASSERT_EQ(0,
                          std::memcmp(read.data_ptr(p, rc, s), reference.data_ptr(p, c, s), bytes))
                    << reference.channelname(c) << " pixel " << p << " sample " << s;
            }
        }
    }
    fs::remove_all(dir);
}

TEST(GBufferWrite, AFailedWriteLeavesNoFile) {
    Rendered r;
    render("cornell_box.gltf", 64, 48, r);
    const fs::path dir = scratch();
    ImageOutputOptions options;
    options.throughOpenExr = true;
    {
        // Rows never written: an error naming them, and nothing in place.
        ImageFileOutput out((dir / "short.exr").string(), options);
        ASSERT_TRUE(out.open(r.spec, gbuffer::channelFormats(r.spec.channelnames)));
        ASSERT_TRUE(out.writeRows(r.flat, OIIO::ROI(0, 64, 0, 16)));
        EXPECT_FALSE(out.commit());
        EXPECT_NE(out.geterror().find("rows 16 to 47 were never written"), std::string::npos);
    }
    EXPECT_FALSE(fs::exists(dir / "short.exr"));
    EXPECT_FALSE(leftovers(dir));
    {
        // An unknown compression name is OpenImageIO's to judge, as before.
        options.compression = "zip:fast";
        ImageFileOutput out((dir / "odd.exr").string(), options);
        out.open(r.spec, gbuffer::channelFormats(r.spec.channelnames));
        EXPECT_FALSE(out.writesThroughOpenExr());
    }
    EXPECT_FALSE(fs::exists(dir / "odd.exr"));
    EXPECT_FALSE(leftovers(dir));
    fs::remove_all(dir);
}

TEST(GBufferWrite, ToolsDefaultDecodesAsOpenExrsDefaultLevelAndNoCompression) {
    // dhdr-gbuffer's default (zip at level 1) against the files of OpenEXR's default level and
    // of no compression, each decoded by the other library.
    const fs::path dir = scratch();
    const std::string scene = std::string(DHDR_TESTDATA) + "/shot.gltf";
    auto run = [&](const std::string& out, const std::string& compression) {
        std::string cmd = std::string(DHDR_TOOLS_DIR) + "/dhdr-gbuffer '" + scene +
                          "' --size 150x100 -q -o '" + (dir / out).string() + "'";
        if (!compression.empty()) cmd += " --compression " + compression;
        return std::system(cmd.c_str());
    };
    ASSERT_EQ(run("default.exr", ""), 0);
    ASSERT_EQ(run("zip.exr", "zip"), 0);
    ASSERT_EQ(run("none.exr", "none"), 0);
    auto in = OIIO::ImageInput::open((dir / "default.exr").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_string_attribute("compression"), "zip");
    const auto reference = decodeWithOpenExr(dir / "none.exr");
    EXPECT_TRUE(decodeWithOiio(dir / "default.exr") == reference);
    EXPECT_TRUE(decodeWithOiio(dir / "zip.exr") == reference);
    EXPECT_TRUE(decodeWithOpenExr(dir / "default.exr") == decodeWithOiio(dir / "none.exr"));
    fs::remove_all(dir);
}
