#pragma once
// One entry point per parser, in libFuzzer's form: glintscope's one-line errors (Error) are the
// expected answer to bad input; anything else (a crash, another exception, a sanitizer report)
// is a bug. Each target file defines LLVMFuzzerTestOneInput; fuzz/CMakeLists.txt links it with
// libFuzzer (clang, GLINTSCOPE_FUZZ=ON) and, in every build, with replay_main.cpp, which feeds
// it each file of a seed corpus under tests/fuzz/ (a ctest per target).
#include <cstddef>
#include <cstdint>
#include <string>

namespace glintscope::fuzz {

// The input as a file with this extension (the readers dispatch on it), removed afterwards.
class InputFile {
public:
    InputFile(const std::uint8_t* data, std::size_t size, const std::string& extension);
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

}  // namespace glintscope::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
