// Files whose headers claim enormous images (PNG, EXR, NPY, TIFF, X3P) are refused from the header,
// in well under a second and 200 MB, with one line and no library chatter (libpng's own
// "libpng error" lines used to appear beside ours).
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_runner.hpp"
#include "zip_files.hpp"
#include "glintscope/surface/heightfield.hpp"
#include "glintscope/io/heightfield_io.hpp"

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

void put_le16(std::string& bytes, std::size_t at, std::uint16_t value) {
    bytes[at] = static_cast<char>(value & 0xff);
    bytes[at + 1] = static_cast<char>(value >> 8);
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

// A little-endian baseline TIFF: one 16-bit grey strip of 8 × 8 samples, whose ImageWidth and
// ImageLength tags (LONG) then claim 100000 × 100000.
std::string tiff_bomb(const TemporaryDirectory& directory) {
    const int entries = 9;
    const std::uint32_t data_offset = 8 + 2 + entries * 12 + 4;
    std::string bytes = std::string("II*\0", 4) + std::string(4, '\0');
    put_le32(bytes, 4, 8);
    std::string ifd(2 + entries * 12 + 4, '\0');
    put_le16(ifd, 0, entries);
    const std::array<std::array<std::uint32_t, 3>, entries> tags = {{{256, 4, 100000}, {257, 4, 100000}, {258, 3, 16},
                                                                      {259, 3, 1}, {262, 3, 1}, {273, 4, data_offset},
                                                                      {277, 3, 1}, {278, 4, 100000}, {279, 4, 128}}};
    for (int k = 0; k < entries; ++k) {
        const std::size_t at = 2 + 12 * k;
        put_le16(ifd, at, static_cast<std::uint16_t>(tags[k][0]));
        put_le16(ifd, at + 2, static_cast<std::uint16_t>(tags[k][1]));
        put_le32(ifd, at + 4, 1);
        if (tags[k][1] == 3)
            put_le16(ifd, at + 8, static_cast<std::uint16_t>(tags[k][2]));
        else
            put_le32(ifd, at + 8, tags[k][2]);
    }
    write_bytes(directory.file("bomb.tif"), bytes + ifd + std::string(128, '\1'));
    return directory.file("bomb.tif");
}

// The tool's own X3P of a small crop, whose main.xml then claims 100000 × 100000 points.
std::string x3p_bomb(const TemporaryDirectory& directory) {
    const CliResult made = run_cli({"convert", "builtin:grating", directory.file("s.x3p"), "--crop", "0,0,2um,2um"});
    EXPECT_EQ(made.exit_code, 0) << made.output;
    std::string xml = read_zip_member(directory.file("s.x3p"), "main.xml");
    for (const std::string tag : {"SizeX", "SizeY"}) {
        const std::size_t open = xml.find("<" + tag + ">"), close = xml.find("</" + tag + ">");
        EXPECT_NE(open, std::string::npos) << tag;
        xml.replace(open + tag.size() + 2, close - open - tag.size() - 2, "100000");
    }
    const std::string data = read_zip_member(directory.file("s.x3p"), "bindata/data.bin");
    EXPECT_TRUE(write_zip(directory.file("bomb.x3p"), {{"main.xml", xml}, {"bindata/data.bin", data}}));
    return directory.file("bomb.x3p");
}

// The peak memory of `glintscope info PATH` alone, in MB: run from a forked child, whose only
// waited-for descendants are that run, so RUSAGE_CHILDREN sees nothing else.
long info_peak_megabytes(const std::string& path, CliResult& result, double& seconds) {
    int channel[2];
    if (::pipe(channel) != 0) return -1;
    const pid_t child = ::fork();
    if (child == 0) {
        ::close(channel[0]);
        const auto start = std::chrono::steady_clock::now();
        const CliResult run = run_cli({"info", path});
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        rusage usage{};
        getrusage(RUSAGE_CHILDREN, &usage);
        const std::string report = std::to_string(run.exit_code) + " " + std::to_string(elapsed) + " " +
                                   std::to_string(usage.ru_maxrss / 1024) + "\n" + run.output;
        [[maybe_unused]] const ssize_t written = ::write(channel[1], report.data(), report.size());
        ::_exit(0);
    }
    ::close(channel[1]);
    std::string report;
    char buffer[4096];
    for (ssize_t n; (n = ::read(channel[0], buffer, sizeof buffer)) > 0;) report.append(buffer, std::size_t(n));
    ::close(channel[0]);
    int status = 0;
    ::waitpid(child, &status, 0);
    long megabytes = -1;
    std::sscanf(report.c_str(), "%d %lf %ld", &result.exit_code, &seconds, &megabytes);
    result.output = report.substr(report.find('\n') + 1);
    return megabytes;
}

TEST(HeaderBomb, EachFormatIsRefusedFromItsHeaderQuicklyAndSmall) {
    const TemporaryDirectory directory;
    for (const std::string& path : {png_bomb(directory), exr_bomb(directory), npy_bomb(directory),
                                    tiff_bomb(directory), x3p_bomb(directory)}) {
        CliResult result;
        double seconds = 0.0;
        [[maybe_unused]] const long megabytes = info_peak_megabytes(path, result, seconds);
        EXPECT_NE(result.exit_code, 0) << path;
        EXPECT_EQ(result.output.find("libpng"), std::string::npos) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_NE(result.output.find("cannot read"), std::string::npos) << result.output;
#ifndef __SANITIZE_ADDRESS__  // AddressSanitizer's start-up, shadow and quarantine alone approach the bounds
        EXPECT_LT(seconds, 10.0) << path;  // refused from the header, not after reading: generous for a loaded CI
        EXPECT_GT(megabytes, 0) << path;
        EXPECT_LT(megabytes, 200) << path;
#endif
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
