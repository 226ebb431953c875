// The parameters of a params struct described once (as Filament's options are): each field's
// command-line option, its Python keyword, what it means, its range or its choices. The
// libraries' checks, the tools' options and --help (ranges and defaults), the Python module's
// keywords and their checks, and the docs (a test holds docs/*.md to these tables) all come
// from here, so that a range, a choice or a default cannot differ between them.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

namespace dhdr {

// A number's range: [lo, hi], open at an end where asked; NaN and ±Inf are never inside.
struct ParamRange {
    double lo, hi;
    bool openLo = false, openHi = false;
    bool contains(double v) const {
        return std::isfinite(v) && (openLo ? v > lo : v >= lo) && (openHi ? v < hi : v <= hi);
    }
    std::string text() const {
        auto number = [](double v) {
            char out[32];
            std::snprintf(out, sizeof out, "%g", v);
            return std::string(out);
        };
        return (openLo ? "(" : "[") + number(lo) + ", " + number(hi) + (openHi ? ")" : "]");
    }
};

// Which name a message gives a parameter: the tools' option ("--ao-samples") or the Python
// keyword ("ao_samples").
enum class Spelling { Option, Keyword };

template <class Params>
struct IntParam {
    const char* option;            // the tools' option, e.g. "--shadow-samples"
    int Params::*field;            // where the value lives
    int min, max;                  // inclusive
    const char* metavar;           // the value's name in --help
    const char* help;              // what it counts, without the range or the default
    const char* keyword = nullptr; // the Python keyword (null: none)
};

// A real number: a float field, or a double one (FloatParam<Params, double>) where the library
// computes in double (the tone map's key, the animation's time).
template <class Params, class T = float>
struct FloatParam {
    const char* option;
    const char* keyword;
    T Params::*field;
    ParamRange range;
    const char* metavar;
    const char* help; // what it is and its unit, without the range or the default
};

// Whole numbers given together ("NX,NY,NZ"), each in [min, max], in a field of that many ints
// (glm::ivec3); all 0, the default, means not given.
template <class Params, class Vec>
struct IntVecParam {
    const char* option;
    const char* keyword;
    Vec Params::*field;
    int min, max; // inclusive, each number
    const char* metavar;
    const char* help;
};

// One of a few names ("off|rt|ssao"), stored as the index of the name (an enum or a bool)
// through `get` and `set`.
template <class Params>
struct ChoiceParam {
    const char* option;
    const char* keyword;
    const char* names; // "a|b|c"
    int (*get)(const Params&);
    void (*set)(Params&, int);
    const char* help;
};

// A switch: given, it sets `get` to !`negated` (--no-shadows: shadows = false).
template <class Params>
struct FlagParam {
    const char* option;
    const char* keyword;
    bool (*get)(const Params&);
    void (*set)(Params&, bool);
    bool negated;
    const char* help;
};

// The name a message gives `p` (its option, or its keyword).
template <class P>
const char* paramName(const P& p, Spelling spelling) {
    return spelling == Spelling::Keyword && p.keyword ? p.keyword : p.option;
}

// Name number `index` of `names` ("a|b|c"); empty past the last.
inline std::string choiceName(const char* names, int index) {
    for (const char* s = names; index >= 0; --index) {
        const char* bar = std::strchr(s, '|');
        if (index == 0) return bar ? std::string(s, bar) : std::string(s);
        if (!bar) break;
        s = bar + 1;
    }
    return {};
}

// The index of `value` among `names`; -1 when it is none of them.
inline int choiceIndex(const char* names, const std::string& value) {
    for (int i = 0;; ++i) {
        const std::string name = choiceName(names, i);
        if (name.empty()) return -1;
        if (name == value) return i;
    }
}

// "a, b or c".
inline std::string choiceList(const char* names) {
    std::string out;
    for (int i = 0; !choiceName(names, i).empty(); ++i) {
        if (i > 0) out += choiceName(names, i + 1).empty() ? " or " : ", ";
        out += choiceName(names, i);
    }
    return out;
}

// Sets `params` to `value` of choice `p`; false with "NAME must be a, b or c" otherwise.
template <class Params>
bool setChoice(const ChoiceParam<Params>& p, Params& params, const std::string& value,
               Spelling spelling, std::string& error) {
    const int index = choiceIndex(p.names, value);
    if (index < 0) {
        error = std::string(paramName(p, spelling)) + " must be " + choiceList(p.names) +
                (spelling == Spelling::Keyword ? ", got '" + value + "'" : "");
        return false;
    }
    p.set(params, index);
    return true;
}

// "[MIN, MAX]" of an IntParam or IntVecParam.
template <class P>
std::string intRangeText(const P& p) {
    return "[" + std::to_string(p.min) + ", " + std::to_string(p.max) + "]";
}

// "NAME: V is outside [MIN, MAX]" when `v` is outside `p`'s range, else empty. A long long, so
// that a caller holding a wider number (a Python int) is told its own value.
template <class Params>
std::string rangeProblem(const IntParam<Params>& p, long long v, Spelling spelling) {
    if (v >= p.min && v <= p.max) return {};
    return std::string(paramName(p, spelling)) + ": " + std::to_string(v) + " is outside " +
           intRangeText(p);
}

// The first field of `params` outside its range, as "NAME: V is outside [MIN, MAX]"; empty
// when all are within.
template <class Params, size_t N>
std::string checkRanges(const Params& params, const IntParam<Params> (&table)[N],
                        Spelling spelling = Spelling::Option) {
    for (const IntParam<Params>& p : table)
        if (std::string e = rangeProblem(p, params.*(p.field), spelling); !e.empty()) return e;
    return {};
}

// "NX,NY,NZ" of an IntVecParam's value.
template <class Vec>
std::string intVecText(const Vec& v) {
    std::string out;
    for (int i = 0; i < int(v.length()); ++i)
        out += (i > 0 ? "," : "") + std::to_string(v[i]);
    return out;
}

// "NAME: V has a number outside [MIN, MAX]" when one of `v`'s numbers is, else empty: the
// check of a value given (all 0 too).
template <class Params, class Vec>
std::string rangeProblem(const IntVecParam<Params, Vec>& p, const Vec& v, Spelling spelling) {
    for (int i = 0; i < int(v.length()); ++i)
        if (v[i] < p.min || v[i] > p.max)
            return std::string(paramName(p, spelling)) + ": " + intVecText(v) +
                   " has a number outside " + intRangeText(p);
    return {};
}

// The rows whose field is given (not all 0).
template <class Params, class Vec, size_t N>
std::string checkRanges(const Params& params, const IntVecParam<Params, Vec> (&table)[N],
                        Spelling spelling = Spelling::Option) {
    for (const IntVecParam<Params, Vec>& p : table)
        if (params.*(p.field) != Vec{})
            if (std::string e = rangeProblem(p, params.*(p.field), spelling); !e.empty()) return e;
    return {};
}

template <class Params, class T, size_t N>
std::string checkRanges(const Params& params, const FloatParam<Params, T> (&table)[N],
                        Spelling spelling = Spelling::Option) {
    for (const FloatParam<Params, T>& p : table) {
        const double v = double(params.*(p.field));
        if (!p.range.contains(v)) {
            char text[32];
            std::snprintf(text, sizeof text, "%g", v);
            return std::string(paramName(p, spelling)) + ": " + text + " is outside " +
                   p.range.text();
        }
    }
    return {};
}

} // namespace dhdr
