// An OpenEXR header made from an OpenImageIO spec, for the files dhdr writes through OpenEXR
// itself (deep G-buffers, and flat ones where OpenImageIO's copies cost more than the
// compression): the attributes OpenImageIO would write, under the names it would write them.
#pragma once

#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenImageIO/imageio.h>
#include <string>

namespace dhdr::detail {

// The windows of `spec` and its attributes: capDate (from DateTime, else now), and strings,
// string lists, ints, floats, doubles, 2- and 3-vectors and 4×4 matrices under their own
// names. OpenImageIO's own ("oiio:", "openexr:") and "compression" are left out; so are
// PixelAspectRatio, screenWindowCenter and screenWindowWidth, which OpenEXR's header holds
// as standard attributes (taken from the spec when it has them).
Imf::Header exrHeaderFromSpec(const OIIO::ImageSpec& spec);

// True when exrHeaderFromSpec writes every attribute of `spec` as OpenImageIO would: none
// of another type, and none that OpenImageIO renames or interprets (Exif:, IPTC:, smpte:,
// ImageDescription …). Else `why` names the first one.
bool exrHeaderKeepsEverything(const OIIO::ImageSpec& spec, std::string& why);

// OpenImageIO's compression names ("zip", "zip:1", "zips", "piz", "rle", "none", "pxr24",
// "b44", "b44a", "dwaa:45", "dwab") as OpenEXR's compression and its level (zip level 1–9 or
// DWA quality; -1: OpenEXR's default). False for a name it does not know.
bool exrCompression(const std::string& name, Imf::Compression& compression, int& level);

// The threads OpenEXR's pool gets: OpenImageIO's "exr_threads" attribute (0: one per core,
// -1: none), as OpenImageIO's own EXR writer applies it.
int exrThreads();

} // namespace dhdr::detail
