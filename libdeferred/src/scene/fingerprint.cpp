#include <OpenImageIO/hash.h>
#include <dhdr/deferred/scene/scene.h>
#include <fstream>
#include <vector>

namespace dhdr {

std::string sceneFingerprint(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return {};
    OIIO::SHA1 sha;
    std::vector<char> block(1 << 20);
    while (file) {
        file.read(block.data(), std::streamsize(block.size()));
        if (file.gcount() > 0) sha.append(block.data(), size_t(file.gcount()));
    }
    if (file.bad()) return {};
    return sha.digest();
}

} // namespace dhdr
