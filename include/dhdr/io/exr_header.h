// A look at an OpenEXR file's headers before OpenEXR reads them. OpenEXR 3.1 (Debian 12)
// allocates what a header claims before reading it: a string attribute of 2 GB in a 200-byte
// file makes it allocate (and zero) 2 GB; a preview of 65535² texels, 16 GB. OpenImageIO 2.4
// aborts the process on a channel of an unknown pixel type. Found by fuzzing
// (docs/development.md, "Fuzzing"); every dhdr reader of EXR files checks here first.
#pragma once

#include <string>

namespace dhdr::detail {

// True when the file at `path` is not an OpenEXR file (another reader's business) or when
// every attribute of its headers fits in the file and every channel has a pixel type
// OpenEXR defines; false with `error` naming the first attribute that claims more bytes than
// the file holds, a channel list with an unknown pixel type (OpenImageIO 2.4 aborts on one)
// or a header cut short.
bool exrHeadersFit(const std::string& path, std::string& error);

} // namespace dhdr::detail
