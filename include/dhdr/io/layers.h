// Finding the colour a tool works on in a file someone else wrote: by channel name, in
// layered (Blender's ViewLayer.Combined.R, Nuke's rgba, renderers' beauty.R) and multi-part
// EXRs, never by channel position.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <dhdr/io/strip_reader.h>
#include <string>
#include <vector>

namespace dhdr {

// One layer holding colour: R, G, B (and maybe A) channels under one prefix, in one part.
struct ColourLayer {
    int subimage = 0;
    std::string part;               // the EXR part's name ("" for a single-part file)
    std::string prefix;             // channels are prefix + "R" …; "" for the unnamed R, G, B, A
    int rgba[4] = {-1, -1, -1, -1}; // channel indices within the part; A may be −1
    std::vector<std::string> partChannels; // every channel name of the part
    int width = 0, height = 0, depth = 1;  // the part's size in pixels

    // How users and messages name the layer: the part and the prefix, joined by '.'.
    std::string name() const;
};

// Every colour layer of `path`, part by part, in channel order. False with `error` when the
// file cannot be opened.
bool listColourLayers(const std::string& path, std::vector<ColourLayer>& layers,
                      std::string& error);

// The layer to work on. With `wanted` (--layer), the layer or part of that name (a full
// name, a part name, a channel prefix, or its last component, case-insensitively, when one
// layer has it). Without: the unnamed R, G, B; else the one layer named by the conventions
// of Blender (Combined), Nuke (rgba) or renderers (beauty); else the only colour layer. When
// none or several qualify, false with an error that lists the layers.
bool chooseColourLayer(const std::vector<ColourLayer>& layers, const std::string& wanted,
                       ColourLayer& chosen, std::string& error);

// What a tool does before reading the colour of `path`: the file exists, its headers fit in
// memory, its layers are listed and `wanted` chosen among them (chooseColourLayer), and the
// layer is within the pixel limit (pixel_limit.h) — all before any pixel is read. False with
// `error` naming the file ("PATH: no such file", …); `layerCount` receives how many colour
// layers the file has. The tools and the Python module find colour through this one call.
bool findColourLayer(const std::string& path, const std::string& wanted, ColourLayer& chosen,
                     size_t& layerCount, std::string& error);

// The pixels of a chosen layer as float, reordered so that channels 0–2 (3) are its R, G, B
// (A) under their own names; with `keepOthers`, the part's other channels follow unchanged,
// else they are left out. `formats` receives each resulting channel's type in the file.
bool readColourLayer(const std::string& path, const ColourLayer& layer, bool keepOthers,
                     int nthreads, OIIO::ImageBuf& image, std::vector<OIIO::TypeDesc>& formats,
                     std::string& error);

// readColourLayer a strip of rows at a time (strip_reader.h): the same channels in the same
// order, for stages that stream their frames.
class ColourStripReader {
public:
    bool open(const std::string& path, const ColourLayer& layer, bool keepOthers, int nthreads,
              std::string& error);
    // The spec of the strips read (float, reordered, the whole frame's size and metadata).
    const OIIO::ImageSpec& spec() const { return m_spec; }
    // The file's type of each channel of spec().
    const std::vector<OIIO::TypeDesc>& formats() const { return m_formats; }
    bool read(int ybegin, int yend, OIIO::ImageBuf& strip, std::string& error);

private:
    StripReader m_reader;
    OIIO::ImageBuf m_raw;
    OIIO::ImageSpec m_spec;
    std::vector<OIIO::TypeDesc> m_formats;
    std::vector<int> m_order; // channels of the raw strip, in the order they are handed out
    bool m_identity = true;
    int m_alpha = -1;
};

} // namespace dhdr
