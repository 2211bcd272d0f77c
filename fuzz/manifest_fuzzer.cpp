// Batch manifests (TOML). Seeds: tests/fuzz/manifest/ (the figures/ manifests). Only the loader
// runs, which checks every key and query before any computation.
#include "fuzz_target.hpp"
#include "glintscope/batch/batch.hpp"
#include "glintscope/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const glintscope::fuzz::InputFile file(data, size, ".toml");
    try {
        glintscope::load_manifest(file.path());
    } catch (const glintscope::Error&) {
    }
    return 0;
}
