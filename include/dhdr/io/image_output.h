// Writing an image so that no reader ever sees half of it: under a temporary name in the
// output's folder, renamed into place when complete, never holding NaN or Inf.
#pragma once

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dhdr {

class DeepScanlineWriter;
class NativeWriter;
namespace detail {
class FlatScanlineWriter;
}

struct ImageOutputOptions {
    // The "Software" attribute written in the header ("dhdr-light (dhdr 0.1.0)"); empty keeps
    // the spec's own.
    std::string software;
    // The file's compression (OpenImageIO's names: "zip", "piz", "dwaa:45" …); empty: the
    // spec's, else the format's default.
    std::string compression;
    // A flat EXR is written through OpenEXR itself rather than OpenImageIO (fewer copies of
    // each strip, docs/gbuffer.md) when every channel is half, float or uint and OpenEXR's
    // header keeps every attribute as OpenImageIO would write it; else through OpenImageIO.
    // The pixels and header are the same either way.
    bool throughOpenExr = false;
};

// An output file written under a temporary name in its folder (".NAME.tmpPID.EXT": same
// extension, so the format is the same) and renamed into place by commit(): a failed or
// interrupted run never leaves a partial file, and the destructor removes an uncommitted one.
// Temporaries of the same output left by a process that is gone (killed with SIGKILL) are
// removed when it is written again. Rows are written as they are produced. Output is
// scanline whatever the input was, and never holds NaN or Inf: NaN becomes 0, ±Inf and
// values past half's ±65504 in half channels the type's largest value, each counted
// (nonFiniteWritten, clampedWritten); a G-buffer's Z keeps the +Inf of its background,
// which the contract gives it. Errors name the output and are kept for geterror(); nothing
// is printed. One caller at a time.
class ImageFileOutput {
public:
    explicit ImageFileOutput(std::string path, ImageOutputOptions options = {});
    ~ImageFileOutput();
    ImageFileOutput(const ImageFileOutput&) = delete;
    ImageFileOutput& operator=(const ImageFileOutput&) = delete;

    // Opens the temporary file for an image of `spec`; rows are then given as pixels.
    // `formats`: one type for all channels, or one per channel; empty keeps float.
    bool open(OIIO::ImageSpec spec, const std::vector<OIIO::TypeDesc>& formats);
    // Opens the temporary file for a deep scanline image of `spec` (its channelformats the
    // samples' types); rows are then given as DeepData. Written through OpenEXR itself
    // (deep_exr.h: OpenImageIO 2.4.7 overflows on large deep frames). EXR only.
    bool openDeep(OIIO::ImageSpec spec);
    bool isOpen() const { return m_out || m_deep || m_flat; }
    // Before open(): ImageOutputOptions::throughOpenExr.
    void setThroughOpenExr(bool on) { m_options.throughOpenExr = on; }
    // Whether the open file is written through OpenEXR itself.
    bool writesThroughOpenExr() const { return bool(m_flat); }
    // The spec the file is written with (after open).
    const OIIO::ImageSpec& spec() const;

    // Rows [ybegin, yend): contiguous float pixels of all channels.
    bool writeRows(int ybegin, int yend, const float* pixels);
    // Rows [rows.ybegin, rows.yend) of `image`, which covers them over the file's width, in
    // any pixel type: float is converted by the rule above, other types by OpenImageIO.
    bool writeRows(const OIIO::ImageBuf& image, OIIO::ROI rows);
    bool writeDeepRows(int ybegin, int yend, const OIIO::DeepData& samples);
    // Closes the file and renames it into place.
    bool commit();

    const std::string& path() const { return m_path; }
    // The last error, "PATH: what went wrong"; cleared when `clear`.
    std::string geterror(bool clear = true) const;
    bool has_error() const { return !m_error.empty(); }
    // Values written as finite ones (NaN → 0, ±Inf → the largest float) and values beyond
    // half's ±65504 clamped to it.
    long long nonFiniteWritten() const { return m_nonFinite; }
    long long clampedWritten() const { return m_clamped; }
    // One line each for the counts above that are not 0, naming the output, for a tool to
    // print as warnings once committed.
    std::vector<std::string> warnings() const;

private:
    bool fail(const std::string& message);
    bool openTemporary(const OIIO::ImageSpec& spec);
    bool openFlatExr(const OIIO::ImageSpec& spec);

    std::string m_path, m_temporary;
    ImageOutputOptions m_options;
    std::unique_ptr<OIIO::ImageOutput> m_out;
    std::unique_ptr<DeepScanlineWriter> m_deep;
    std::unique_ptr<detail::FlatScanlineWriter> m_flat;
    std::unique_ptr<NativeWriter> m_native; // null: OIIO converts (8/16-bit formats)
    OIIO::ImageSpec m_ownSpec;              // of m_deep or m_flat
    std::vector<std::byte> m_buffer;
    std::vector<float> m_floats;
    long long m_clamped = 0, m_nonFinite = 0;
    bool m_committed = false;
    mutable std::string m_error;
};

// Writes `path` through `write`, which fills the temporary it is given (keeping the
// extension) and returns false with a reason; renamed into place only when complete. False
// with `error` ("PATH: cannot write: …") otherwise.
bool writeFileAtomically(const std::string& path,
                         const std::function<bool(const std::string&, std::string&)>& write,
                         std::string& error);

// From now on, every temporary output open in the process (ImageFileOutput,
// writeFileAtomically) is removed when the process ends on SIGHUP, SIGINT, SIGTERM or SIGQUIT
// — unless the process was started with that signal ignored (`nohup`), which then stays
// ignored — or on a fatal signal (SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL). The tools call
// it first thing; a host program with handlers of its own leaves it out.
void removeTemporaryOutputsOnSignals();

} // namespace dhdr
