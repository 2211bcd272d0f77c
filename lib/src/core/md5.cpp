// MD5 message digest, RFC 1321 §3.
#include "md5.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace glintscope {
namespace {

// Per-step shift amounts of the four rounds (RFC 1321 §3.4).
constexpr std::array<int, 16> kShifts = {7, 12, 17, 22, 5, 9, 14, 20, 4, 11, 16, 23, 6, 10, 15, 21};

// T[i] = floor(2^32 · |sin(i + 1)|) (RFC 1321 §3.4); the test vectors check every entry's use.
std::array<std::uint32_t, 64> sine_table() {
    std::array<std::uint32_t, 64> table{};
    for (int i = 0; i < 64; ++i)
        table[i] = static_cast<std::uint32_t>(std::floor(std::fabs(std::sin(i + 1.0)) * 4294967296.0));
    return table;
}

void process_block(const unsigned char* block, std::array<std::uint32_t, 4>& state) {
    static const std::array<std::uint32_t, 64> sines = sine_table();
    std::uint32_t words[16];
    for (int i = 0; i < 16; ++i)
        words[i] = std::uint32_t{block[4 * i]} | std::uint32_t{block[4 * i + 1]} << 8 |
                   std::uint32_t{block[4 * i + 2]} << 16 | std::uint32_t{block[4 * i + 3]} << 24;
    auto [a, b, c, d] = state;
    for (int i = 0; i < 64; ++i) {
        const int round = i / 16;
        std::uint32_t mixed = 0;
        int word = 0;
        switch (round) {
            case 0:
                mixed = (b & c) | (~b & d);
                word = i;
                break;
            case 1:
                mixed = (d & b) | (~d & c);
                word = (5 * i + 1) % 16;
                break;
            case 2:
                mixed = b ^ c ^ d;
                word = (3 * i + 5) % 16;
                break;
            default:
                mixed = c ^ (b | ~d);
                word = (7 * i) % 16;
                break;
        }
        mixed += a + sines[i] + words[word];
        a = d;
        d = c;
        c = b;
        b += std::rotl(mixed, kShifts[round * 4 + i % 4]);
    }
    state[0] += a;
    state[1] += b;
    state[2] += c;
    state[3] += d;
}

}  // namespace

std::string md5_hex(const void* data, std::size_t size) {
    std::array<std::uint32_t, 4> state = {0x67452301u, 0xefcdab89u, 0x98badcfeu, 0x10325476u};
    const auto* bytes = static_cast<const unsigned char*>(data);
    std::size_t full_blocks = size / 64;
    for (std::size_t i = 0; i < full_blocks; ++i) process_block(bytes + 64 * i, state);

    // Padding (§3.1–3.2): a 1 bit, zeros up to 56 mod 64 bytes, then the bit length, little-endian.
    unsigned char tail[128] = {};
    const std::size_t remainder = size - 64 * full_blocks;
    if (remainder > 0) std::memcpy(tail, bytes + 64 * full_blocks, remainder);
    tail[remainder] = 0x80;
    const std::size_t tail_size = remainder < 56 ? 64 : 128;
    const std::uint64_t bit_length = static_cast<std::uint64_t>(size) * 8;
    for (int i = 0; i < 8; ++i) tail[tail_size - 8 + i] = static_cast<unsigned char>(bit_length >> (8 * i));
    for (std::size_t offset = 0; offset < tail_size; offset += 64) process_block(tail + offset, state);

    static const char kHex[] = "0123456789abcdef";
    std::string digest;
    for (std::uint32_t word : state)
        for (int i = 0; i < 4; ++i) {
            const unsigned byte = (word >> (8 * i)) & 0xffu;
            digest += kHex[byte >> 4];
            digest += kHex[byte & 0xfu];
        }
    return digest;
}

}  // namespace glintscope
