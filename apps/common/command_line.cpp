#include "command_line.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dhdr::app {

CommandLine::CommandLine(std::string tool, std::string synopsis, std::string description)
    : m_tool(std::move(tool)), m_synopsis(std::move(synopsis)),
      m_description(std::move(description)) {}

void CommandLine::flag(const std::string& name, bool& target, const std::string& help) {
    Option o;
    o.name = name;
    o.help = help;
    o.flag = &target;
    m_options.push_back(std::move(o));
}

void CommandLine::flag(const std::string& name, std::function<void()> given,
                       const std::string& help) {
    Option o;
    o.name = name;
    o.help = help;
    o.given = std::move(given);
    m_options.push_back(std::move(o));
}

void CommandLine::option(const std::string& name, const std::string& metavar,
                         const std::string& help,
                         std::function<bool(const std::string&, std::string&)> parse) {
    Option o;
    o.name = name;
    o.metavar = metavar;
    o.help = help;
    o.parse = std::move(parse);
    m_options.push_back(std::move(o));
}

namespace {
std::string withDefault(const std::string& help, const std::string& value);
std::string numberText(double v);
} // namespace

void CommandLine::option(const std::string& name, std::string& target, const std::string& metavar,
                         const std::string& help) {
    option(name, metavar, withDefault(help, target), [&target](const std::string& v, std::string&) {
        target = v;
        return true;
    });
}

void CommandLine::namesFile(const std::string& name, FileRole role,
                            std::function<std::string(const std::string&)> path) {
    for (Option& o : m_options)
        if (o.name == name) {
            o.role = role;
            o.filePath = std::move(path);
        }
}

namespace {

// strtod reads hexadecimal too ("0x18" is 24): the tools' numbers are decimal, as documented.
bool isHexadecimal(const std::string& v) {
    return v.find_first_of("xX") != std::string::npos;
}

// `v` as a finite number in `d`; false with the message otherwise.
bool parseFinite(const std::string& v, double& d, std::string& err) {
    char* end = nullptr;
    d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(d) || isHexadecimal(v)) {
        err = "'" + v + "' is not a finite decimal number";
        return false;
    }
    return true;
}

// `help` and the default the option's variable holds before parsing, unless the help says
// what the default is in words: every default shown is the value the tool starts from.
std::string withDefault(const std::string& help, const std::string& value) {
    if (help.find("default") != std::string::npos || value.empty()) return help;
    return help + " (default " + value + ")";
}

std::string numberText(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

} // namespace

void CommandLine::option(const std::string& name, double& target, const std::string& metavar,
                         const std::string& help, Range range) {
    option(name, metavar, withDefault(help, numberText(target)) + " " + range.text(),
           [&target, range](const std::string& v, std::string& err) {
               double d = 0.0;
               if (!parseFinite(v, d, err)) return false;
               if (!range.contains(d)) {
                   err = v + " is outside " + range.text();
                   return false;
               }
               target = d;
               return true;
           });
}

namespace {

// The number `v` (as given) checked as the float it becomes against `range`; empty when fine.
std::string checkAsFloat(const std::string& v, double d, const CommandLine::Range& range) {
    if (!range.contains(d)) return v + " is outside " + range.text();
    // Against the range's ends as floats too: 1e30 is not a float, and the float nearest it
    // is a little larger. Compared float to float, so that the value and the ends are rounded
    // alike whatever the optimizer keeps in double (with -O3 -fPIC, GCC 12 compared the rounded
    // value against the unrounded end and refused the end itself).
    const float f = float(d), lo = float(range.lo), hi = float(range.hi);
    const bool inside =
        std::isfinite(f) && (range.openLo ? f > lo : f >= lo) && (range.openHi ? f < hi : f <= hi);
    if (!inside) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", double(f));
        return v + " is outside " + range.text() + " as a float (" + text + ")";
    }
    return {};
}

void requireFloatRange(const std::string& name, const CommandLine::Range& range) {
    const double largest = double(std::numeric_limits<float>::max());
    if (!(std::fabs(range.lo) <= largest && std::fabs(range.hi) <= largest))
        throw std::logic_error(name + ": the range of a float option must fit a float");
}

} // namespace

void CommandLine::option(const std::string& name, float& target, const std::string& metavar,
                         const std::string& help, Range range) {
    requireFloatRange(name, range);
    option(name, metavar, withDefault(help, numberText(double(target))) + " " + range.text(),
           [&target, range](const std::string& v, std::string& err) {
               double d = 0.0;
               if (!parseFinite(v, d, err)) return false;
               if (err = checkAsFloat(v, d, range); !err.empty()) return false;
               target = float(d);
               return true;
           });
}

void CommandLine::option(const std::string& name, int& target, const std::string& metavar,
                         const std::string& help, int lo, int hi) {
    const Range range{double(lo), double(hi)};
    // Whole numbers in full: %g would show 999999999 as 1e+09.
    const std::string rangeText = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    option(name, metavar, withDefault(help, std::to_string(target)) + " " + rangeText,
           [&target, range, rangeText](const std::string& v, std::string& err) {
               char* end = nullptr;
               errno = 0;
               const long long n = std::strtoll(v.c_str(), &end, 10);
               if (v.empty() || *end != '\0') {
                   err = "'" + v + "' is not a whole number";
                   return false;
               }
               if (errno == ERANGE || !range.contains(double(n))) {
                   err = v + " is outside " + rangeText;
                   return false;
               }
               target = int(n);
               return true;
           });
}

void CommandLine::printHelp() const {
    std::printf("Usage: %s %s\n\n%s\n\nOptions:\n", m_tool.c_str(), m_synopsis.c_str(),
                m_description.c_str());
    auto row = [](const std::string& left, const std::string& help) {
        if (left.size() > 26)
            std::printf("  %s\n  %-26s %s\n", left.c_str(), "", help.c_str());
        else
            std::printf("  %-26s %s\n", left.c_str(), help.c_str());
    };
    row("-o, --output FILE", "output file (written to a temporary name, then renamed)");
    for (const Option& o : m_options)
        row(o.name + (o.metavar.empty() ? "" : " " + o.metavar), o.help);
    row("--compression NAME", "output compression, e.g. zip, zips, piz, none for EXR; zip:1 "
                              "for a faster zip (default: the format's)");
    row("--frames A-B", m_framesHelp);
    row("--threads N", "worker threads (0: one per core; default " +
                           std::to_string(kDefaultThreads) + ") [0, " +
                           std::to_string(kMaxThreads) + "]");
    row("--max-pixels N",
        "refuse an image of more than N pixels (width x height) before reading it (default " +
            std::to_string(kDefaultMaxPixels) + " = 16384x16384; 0: no limit)");
    row("-v, --verbose", "report what is measured and done");
    row("-q, --quiet", "print nothing but errors");
    row("-h, --help", "show this help and exit");
    row("--", "end of the options: what follows are files (a name beginning with '-')");
    row("--version", "show the version and exit");
    if (!m_epilog.empty()) std::printf("\n%s\n", m_epilog.c_str());
    std::printf("\nExit status: 0 success, 1 failure, 2 usage error.\n");
}

bool CommandLine::given(const std::string& name) const {
    return std::find(m_given.begin(), m_given.end(), name) != m_given.end();
}

int CommandLine::usageError(const std::string& message) const {
    std::fprintf(stderr, "%s: usage error: %s\nTry '%s --help'.\n", m_tool.c_str(), message.c_str(),
                 m_tool.c_str());
    return kExitUsage;
}

void CommandLine::flagWithNumber(const std::string& name, bool& given, std::optional<double>& value,
                                 const std::string& metavar, const std::string& help, Range range) {
    requireFloatRange(name, range);
    Option o;
    o.name = name;
    o.metavar = "[" + metavar + "]";
    o.help = help + " " + range.text();
    o.numberRange = range;
    o.flag = &given;
    o.number = &value;
    m_options.push_back(o);
}

int CommandLine::parse(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        // `--` ends the options: what follows are files, whatever their names (-x.exr).
        if (arg == "--") {
            m_inputs.insert(m_inputs.end(), argv + i + 1, argv + argc);
            break;
        }
        std::string value;
        bool hasValue = false;
        if (arg.rfind("--", 0) == 0) {
            if (const size_t eq = arg.find('='); eq != std::string::npos) {
                value = arg.substr(eq + 1);
                arg = arg.substr(0, eq);
                hasValue = true;
            }
        }
        auto takeValue = [&](std::string& out) {
            if (hasValue) {
                out = value;
                return true;
            }
            if (i + 1 >= argc) return false;
            out = argv[++i];
            return true;
        };
        if (arg == "-h" || arg == "--help") {
            printHelp();
            return kExitSuccess;
        }
        if (arg == "--version") {
            std::printf("%s (dhdr) %s\n", m_tool.c_str(), DHDR_VERSION);
            return kExitSuccess;
        }
        if (arg == "-v" || arg == "--verbose") {
            m_verbosity = 2;
            continue;
        }
        if (arg == "-q" || arg == "--quiet") {
            m_verbosity = 0;
            continue;
        }
        if (arg == "-o" || arg == "--output") {
            if (!takeValue(m_output)) return usageError(arg + " needs a file name");
            continue;
        }
        if (arg == "--frames") {
            if (!takeValue(m_frames)) return usageError("--frames needs A-B");
            continue;
        }
        if (arg == "--compression") {
            if (!takeValue(m_compression)) return usageError("--compression needs a name");
            continue;
        }
        if (arg == "--threads") {
            std::string v;
            char* end = nullptr;
            if (!takeValue(v)) return usageError("--threads needs a number");
            errno = 0;
            const long n = std::strtol(v.c_str(), &end, 10);
            if (v.empty() || *end != '\0' || errno == ERANGE || n < 0 || n > kMaxThreads)
                return usageError("--threads: '" + v + "' is not a count of threads in [0, " +
                                  std::to_string(kMaxThreads) + "]");
            m_threads = int(n);
            continue;
        }
        if (arg == "--max-pixels") {
            std::string v;
            char* end = nullptr;
            if (!takeValue(v)) return usageError("--max-pixels needs a number");
            errno = 0;
            const long long n = std::strtoll(v.c_str(), &end, 10);
            if (v.empty() || *end != '\0' || errno == ERANGE || n < 0)
                return usageError("--max-pixels: '" + v +
                                  "' is not a count of pixels (0: no limit)");
            m_maxPixels = n;
            continue;
        }
        if (arg.size() > 1 && arg[0] == '-') {
            const Option* found = nullptr;
            for (const Option& o : m_options)
                if (o.name == arg) found = &o;
            if (!found) {
                std::error_code ec;
                const bool isFile = std::filesystem::exists(argv[i], ec);
                return usageError(
                    "unknown option " + arg +
                    (isFile ? " (a file whose name begins with '-' goes after --: " + m_tool +
                                  " [options] -- " + std::string(argv[i]) + ")"
                            : std::string()));
            }
            m_given.push_back(arg);
            if (found->number) {
                *found->flag = true;
                std::string v = hasValue ? value : (i + 1 < argc ? argv[i + 1] : "");
                char* end = nullptr;
                const double d = std::strtod(v.c_str(), &end);
                const bool isNumber =
                    !v.empty() && *end == '\0' && std::isfinite(d) && !isHexadecimal(v);
                if (hasValue && !isNumber) return usageError(arg + ": '" + v + "' is not a number");
                if (isNumber)
                    if (const std::string e = checkAsFloat(v, d, found->numberRange); !e.empty())
                        return usageError(arg + ": " + e);
                if (isNumber) {
                    *found->number = d;
                    if (!hasValue) ++i;
                }
                continue;
            }
            if (found->flag || found->given) {
                if (hasValue) return usageError(arg + " takes no value");
                if (found->flag) *found->flag = true;
                if (found->given) found->given();
                continue;
            }
            std::string v, err;
            if (!takeValue(v)) return usageError(arg + " needs a value (" + found->metavar + ")");
            if (!found->parse(v, err)) return usageError(arg + ": " + err);
            if (found->role) {
                const std::string file = found->filePath ? found->filePath(v) : v;
                if (!file.empty())
                    (*found->role == FileRole::Input ? m_inputFiles : m_outputFiles)
                        .push_back({arg, file});
            }
            continue;
        }
        m_inputs.push_back(arg);
    }
    setMaxPixels(m_maxPixels);
    return -1;
}

bool parseSize(const std::string& text, int& width, int& height) {
    const size_t x = text.find_first_of("xX");
    if (x == std::string::npos) return false;
    char* end = nullptr;
    const long w = std::strtol(text.c_str(), &end, 10);
    if (end != text.c_str() + x) return false;
    const long h = std::strtol(text.c_str() + x + 1, &end, 10);
    if (*end != '\0' || w <= 0 || h <= 0 || w > 65536 || h > 65536) return false;
    width = int(w);
    height = int(h);
    return true;
}

bool parseNumbers(const std::string& text, std::vector<double>& values, size_t count) {
    values.clear();
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        char* end = nullptr;
        const double d = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(d) || isHexadecimal(item)) return false;
        values.push_back(d);
    }
    return count == 0 ? !values.empty() : values.size() == count;
}

std::string floatProblem(double value, const std::string& text) {
    const float f = float(value);
    if (!std::isfinite(f)) return text + " is more than a float holds (3.4e38 in magnitude)";
    return {};
}

bool parseFloatNumbers(const std::string& text, std::vector<double>& values, size_t count,
                       std::string& error) {
    if (!parseNumbers(text, values, count)) return false;
    std::stringstream in(text);
    std::string item;
    for (double v : values) {
        std::getline(in, item, ',');
        if (error = floatProblem(v, item); !error.empty()) return false;
    }
    return true;
}

} // namespace dhdr::app
