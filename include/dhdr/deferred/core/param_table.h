// The numeric parameters of a params struct described once (as Filament's options are): each
// field's command-line option, what it counts and its range. The library's validate(), the
// tools' options and --help, and the docs (a test holds docs/*.md to these tables) all come
// from here, so that a range cannot differ between them.
#pragma once

#include <string>

namespace dhdr {

template <class Params>
struct IntParam {
    const char* option;  // the tools' option, e.g. "--shadow-samples"
    int Params::*field;  // where the value lives
    int min, max;        // inclusive
    const char* metavar; // the value's name in --help
    const char* help;    // what it counts, without the range or the default
};

// The first field of `params` outside its range, as "--option: V is outside MIN-MAX"; empty
// when all are within.
template <class Params, size_t N>
std::string checkRanges(const Params& params, const IntParam<Params> (&table)[N]) {
    for (const IntParam<Params>& p : table) {
        const int v = params.*(p.field);
        if (v < p.min || v > p.max)
            return std::string(p.option) + ": " + std::to_string(v) + " is outside " +
                   std::to_string(p.min) + "-" + std::to_string(p.max);
    }
    return {};
}

} // namespace dhdr
