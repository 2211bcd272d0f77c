// Heightfield readers: the first byte picks the format (NPY, X3P, EXR, PNG, TIFF), the rest is
// the file. Seeds: tests/fuzz/heightfield/ (a format byte, then a small valid file).
#include <array>
#include <string>

#include "fuzz_target.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/io/heightfield_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::array<std::string, 5> extensions = {".npy", ".x3p", ".exr", ".png", ".tif"};
    if (size < 1) return 0;
    const glintscope::fuzz::InputFile file(data + 1, size - 1, extensions[data[0] % extensions.size()]);
    try {
        glintscope::load_heightfield(file.path());
    } catch (const glintscope::Error&) {
        // The expected answer to a bad file.
    }
    return 0;
}
