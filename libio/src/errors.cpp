#include <dhdr/io/errors.h>
#include <dhdr/io/pixel_limit.h>

namespace dhdr {

std::string oneLine(std::string message) {
    while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
        message.pop_back();
    for (char& c : message)
        if (c == '\n') c = ' ';
    return message.empty() ? "unknown error" : message;
}

std::string cannotRead(const std::string& path, const std::string& error) {
    if (path.find('?') != std::string::npos &&
        error.find("malformed filename") != std::string::npos)
        return path + ": cannot read: OpenImageIO takes what follows '?' in a file name for "
                      "options (file.exr?key=value); rename the file without '?'";
    return path + (isPixelLimitError(error) ? ": " : ": cannot read: ") + oneLine(error);
}

} // namespace dhdr
