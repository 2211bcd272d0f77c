// NPY arrays as NumPy writes them beyond little-endian C-order floats: Fortran order (transposed
// on read), big-endian and integer dtypes read back the exact values at the right samples.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/io/heightfield_io.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

// An NPY 1.0 file of `rows` × `cols` items given as raw bytes in file order.
void write_npy_bytes(const std::string& path, const std::string& descr, bool fortran, int rows, int cols,
                     const std::string& data) {
    std::string header = "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") +
                         ", 'shape': (" + std::to_string(rows) + ", " + std::to_string(cols) + "), }";
    while ((10 + header.size() + 1) % 64) header += ' ';
    header += '\n';
    std::ofstream out(path, std::ios::binary);
    out.write("\x93NUMPY\x01\x00", 8);
    const char length[2] = {static_cast<char>(header.size() & 0xff), static_cast<char>(header.size() >> 8)};
    out.write(length, 2);
    out << header << data;
}

template <typename T>
std::string bytes_of(const std::vector<T>& values, bool big_endian) {
    std::string bytes;
    for (const T value : values) {
        char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof value);
        for (std::size_t k = 0; k < sizeof(T); ++k) bytes += raw[big_endian ? sizeof(T) - 1 - k : k];
    }
    return bytes;
}

// The 2 × 3 array [[1, 2, 3], [4, 5, 6]] (row 0 on top) in every layout must load alike.
void expect_one_to_six(const Heightfield& field) {
    ASSERT_EQ(field.rows, 2);
    ASSERT_EQ(field.cols, 3);
    for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(field.at(r, c), float(1 + 3 * r + c)) << r << "," << c;
}

TEST(NpyVariants, FortranOrderIsTransposedOnRead) {
    const TemporaryDirectory directory;
    // Column-major: (0,0) (1,0) (0,1) (1,1) (0,2) (1,2).
    write_npy_bytes(directory.file("f.npy"), "<f8", true, 2, 3, bytes_of<double>({1, 4, 2, 5, 3, 6}, false));
    expect_one_to_six(load_heightfield(directory.file("f.npy")));
}

TEST(NpyVariants, BigEndianAndIntegerDtypesReadTheirValues) {
    const TemporaryDirectory directory;
    const std::vector<int> values = {1, 2, 3, 4, 5, 6};
    const auto as = [&](auto type) {
        std::vector<decltype(type)> typed;
        for (int v : values) typed.push_back(static_cast<decltype(type)>(v));
        return typed;
    };
    const std::vector<std::pair<std::string, std::string>> files = {
        {">f4", bytes_of(as(float{}), true)},          {">f8", bytes_of(as(double{}), true)},
        {"<i2", bytes_of(as(std::int16_t{}), false)}, {">i4", bytes_of(as(std::int32_t{}), true)},
        {"|u1", bytes_of(as(std::uint8_t{}), false)}, {"<u8", bytes_of(as(std::uint64_t{}), false)},
        {"|i1", bytes_of(as(std::int8_t{}), false)},  {">u2", bytes_of(as(std::uint16_t{}), true)}};
    for (const auto& [descr, data] : files) {
        SCOPED_TRACE(descr);
        write_npy_bytes(directory.file("v.npy"), descr, false, 2, 3, data);
        expect_one_to_six(load_heightfield(directory.file("v.npy")));
    }
    write_npy_bytes(directory.file("neg.npy"), ">i2", false, 1, 2, bytes_of<std::int16_t>({-300, 7}, true));
    const Heightfield negative = load_heightfield(directory.file("neg.npy"));
    EXPECT_EQ(negative.at(0, 0), -300.0f);
    EXPECT_EQ(negative.at(0, 1), 7.0f);
}

TEST(NpyVariants, UnsupportedDtypesAreNamed) {
    const TemporaryDirectory directory;
    for (const std::string descr : {"<c8", "<f2", "<U4", "<f16", "O"}) {
        write_npy_bytes(directory.file("bad.npy"), descr, false, 1, 1, std::string(8, '\0'));
        try {
            load_heightfield(directory.file("bad.npy"));
            ADD_FAILURE() << descr << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("NPY dtype '" + descr + "' is not supported"), std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
}  // namespace glintscope
