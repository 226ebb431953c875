// The shape of the messages dhdr's readers and writers give: one line, naming the file.
#pragma once

#include <string>

namespace dhdr {

// `message` on one line: OpenImageIO's and OpenEXR's messages end in newlines and sometimes
// span several; "unknown error" when empty.
std::string oneLine(std::string message);

// "PATH: cannot read: ERROR", or "PATH: ERROR" for an image over the pixel limit
// (pixel_limit.h), whose message says what is wrong by itself; a name holding '?' that
// OpenImageIO refused gets the reason.
std::string cannotRead(const std::string& path, const std::string& error);

} // namespace dhdr
