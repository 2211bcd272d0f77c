#include "fuzz_target.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace glintscope::fuzz {

InputFile::InputFile(const std::uint8_t* data, std::size_t size, const std::string& extension) {
    static std::atomic<unsigned> counter{0};
    path_ = (std::filesystem::temp_directory_path() /
             ("glintscope-fuzz-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + extension))
                .string();
    std::ofstream(path_, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

InputFile::~InputFile() { std::remove(path_.c_str()); }

}  // namespace glintscope::fuzz
