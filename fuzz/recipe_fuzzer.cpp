// Recipe text (generate --recipe). Seeds: tests/fuzz/recipe/ (the recipes in heightfields/).
// Only the parser runs: generating a valid recipe's surface is not what is being fuzzed.
#include <string>

#include "fuzz_target.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        glintscope::parse_recipe_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.recipe");
    } catch (const glintscope::Error&) {
    }
    return 0;
}
