// Files whose headers claim enormous images (decompression bombs) are refused from the header,
// in well under a second and 200 MB, with one line and no library chatter (libpng's own
// "libpng error" lines used to appear beside ours).
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_runner.hpp"
#include "glintscope/heightfield.hpp"
#include "glintscope/heightfield_io.hpp"

namespace glintscope::testing {
namespace {

std::string read_bytes(const std::string& path) {
    std::ifstream stream(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

void put_be32(std::string& bytes, std::size_t at, std::uint32_t value) {
    for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<char>((value >> (24 - 8 * k)) & 0xff);
}

void put_le32(std::string& bytes, std::size_t at, std::uint32_t value) {
    for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<char>((value >> (8 * k)) & 0xff);
}

// CRC-32 of PNG chunks (ISO 3309 polynomial, reflected).
std::uint32_t crc32(const std::string& bytes, std::size_t begin, std::size_t end) {
    std::uint32_t crc = 0xffffffffu;
    for (std::size_t i = begin; i < end; ++i) {
        crc ^= static_cast<unsigned char>(bytes[i]);
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

// A valid 16² image written by the tool, whose header then claims 40000².
std::string small_image(const TemporaryDirectory& directory, const std::string& name) {
    Heightfield field = make_heightfield(16, 16, 1.0);
    for (std::size_t i = 0; i < field.heights_um.size(); ++i) field.heights_um[i] = float(i % 7) * 0.01f;
    const std::string path = directory.file(name);
    save_heightfield(path, field);
    return path;
}

std::string png_bomb(const TemporaryDirectory& directory) {
    const CliResult made = run_cli({"preview", "builtin:grating", "-o", directory.file("g.png")});
    EXPECT_EQ(made.exit_code, 0) << made.output;
    std::string bytes = read_bytes(directory.file("g.png"));
    put_be32(bytes, 16, 40000);  // IHDR: width, height after the signature and the chunk header
    put_be32(bytes, 20, 40000);
    put_be32(bytes, 29, crc32(bytes, 12, 29));
    write_bytes(directory.file("bomb.png"), bytes);
    return directory.file("bomb.png");
}

std::string exr_bomb(const TemporaryDirectory& directory) {
    std::string bytes = read_bytes(small_image(directory, "small.exr"));
    const std::string attribute = std::string("dataWindow") + '\0' + "box2i" + '\0';
    const std::size_t at = bytes.find(attribute);
    EXPECT_NE(at, std::string::npos);
    const std::size_t box = at + attribute.size() + 4;  // after the attribute's size
    put_le32(bytes, box + 8, 39999);                     // xMax, yMax
    put_le32(bytes, box + 12, 39999);
    write_bytes(directory.file("bomb.exr"), bytes);
    return directory.file("bomb.exr");
}

std::string npy_bomb(const TemporaryDirectory& directory) {
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (100000, 100000), }";
    while ((10 + header.size() + 1) % 64) header += ' ';
    header += '\n';
    std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
    bytes += static_cast<char>(header.size() & 0xff);
    bytes += static_cast<char>(header.size() >> 8);
    write_bytes(directory.file("bomb.npy"), bytes + header + std::string(64, '\0'));
    return directory.file("bomb.npy");
}

TEST(HeaderBomb, EachFormatIsRefusedFromItsHeaderQuicklyAndSmall) {
    const TemporaryDirectory directory;
    for (const std::string& path : {png_bomb(directory), exr_bomb(directory), npy_bomb(directory)}) {
        const auto start = std::chrono::steady_clock::now();
        const CliResult result = run_cli({"info", path});
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        rusage usage{};
        getrusage(RUSAGE_CHILDREN, &usage);
        EXPECT_NE(result.exit_code, 0) << path;
        EXPECT_EQ(result.output.find("libpng"), std::string::npos) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_NE(result.output.find("cannot read"), std::string::npos) << result.output;
        EXPECT_LT(seconds, 1.0) << path;
        EXPECT_LT(usage.ru_maxrss, 200 * 1024) << path;  // KB, the largest child so far
    }
}

TEST(HeaderBomb, TruncatedPngFailsWithOurLineOnly) {
    const TemporaryDirectory directory;
    ASSERT_EQ(run_cli({"preview", "builtin:grating", "-o", directory.file("g.png")}).exit_code, 0);
    const std::string bytes = read_bytes(directory.file("g.png"));
    write_bytes(directory.file("cut.png"), bytes.substr(0, bytes.size() / 2));
    const CliResult result = run_cli({"info", directory.file("cut.png")});
    EXPECT_NE(result.exit_code, 0);
    EXPECT_EQ(result.output.find("libpng"), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
}

}  // namespace
}  // namespace glintscope::testing
