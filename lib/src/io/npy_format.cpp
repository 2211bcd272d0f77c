// NumPy .npy arrays (format versions 1.0, 2.0 and 3.0, as specified in numpy.lib.format):
// a magic string, a little-endian header length, a Python dict literal with 'descr',
// 'fortran_order' and 'shape', then the raw data. Heightfields are 2-D arrays of shape (rows,
// cols) — float32/64 or integers of 1-8 bytes, either byte order, C or Fortran order (transposed
// on read) — array row 0 = heightfield row 0 = the top (largest y),
// as an array shown with matplotlib's imshow. NPY carries no units, so a loaded field has
// units_assumed unless the options supply them, and the texel size is not saved.
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string_view>
#include <utility>
#include <vector>

#include "formats.hpp"

namespace glintscope {
namespace {

static_assert(std::endian::native == std::endian::little, "the NPY reader and writer assume a little-endian host");

constexpr char kMagic[] = "\x93NUMPY";
constexpr std::size_t kMagicSize = 6;

struct NpyHeader {
    std::string descr;
    bool fortran_order = false;
    std::vector<long long> shape;
    bool has_descr = false;
    bool has_fortran_order = false;
    bool has_shape = false;
};

// A parser for the one Python literal NumPy writes: {'key': value, ...} where a value is a
// quoted string, True/False or a tuple of integers.
class HeaderParser {
public:
    HeaderParser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

    NpyHeader parse() {
        NpyHeader header;
        expect('{');
        while (!consume('}')) {
            const std::string key = parse_string();
            expect(':');
            if (key == "descr") {
                header.descr = parse_string();
                header.has_descr = true;
            } else if (key == "fortran_order") {
                header.fortran_order = parse_bool();
                header.has_fortran_order = true;
            } else if (key == "shape") {
                header.shape = parse_shape();
                header.has_shape = true;
            } else {
                throw fail("unexpected key '" + key + "'");
            }
            if (!consume(',')) {
                expect('}');
                break;
            }
        }
        if (!header.has_descr || !header.has_fortran_order || !header.has_shape)
            throw fail("'descr', 'fortran_order' or 'shape' is missing");
        return header;
    }

private:
    Error fail(const std::string& problem) const { return read_error(path_, "corrupt NPY header: " + problem); }

    void skip_space() {
        while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    }
    bool consume(char ch) {
        skip_space();
        if (pos_ < text_.size() && text_[pos_] == ch) {
            ++pos_;
            return true;
        }
        return false;
    }
    void expect(char ch) {
        if (!consume(ch)) throw fail(std::string("expected '") + ch + "'");
    }
    std::string parse_string() {
        skip_space();
        if (pos_ >= text_.size() || (text_[pos_] != '\'' && text_[pos_] != '"')) throw fail("expected a string");
        const char quote = text_[pos_++];
        const std::size_t end = text_.find(quote, pos_);
        if (end == std::string_view::npos) throw fail("unterminated string");
        std::string value(text_.substr(pos_, end - pos_));
        pos_ = end + 1;
        return value;
    }
    bool parse_bool() {
        skip_space();
        for (const auto& [word, value] : {std::pair{"True", true}, std::pair{"False", false}}) {
            const std::size_t length = std::strlen(word);
            if (text_.substr(pos_, length) == word) {
                pos_ += length;
                return value;
            }
        }
        throw fail("expected True or False");
    }
    long long parse_integer() {
        skip_space();
        long long value = 0;
        std::size_t digits = 0;
        while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) {
            if (++digits > 15) throw fail("dimension too large");
            value = value * 10 + (text_[pos_++] - '0');
        }
        if (digits == 0) throw fail("expected a dimension");
        if (pos_ < text_.size() && text_[pos_] == 'L') ++pos_;  // Python 2 long literals
        return value;
    }
    std::vector<long long> parse_shape() {
        expect('(');
        std::vector<long long> shape;
        while (!consume(')')) {
            shape.push_back(parse_integer());
            if (!consume(',')) {
                expect(')');
                break;
            }
        }
        return shape;
    }

    std::string_view text_;
    const std::string& path_;
    std::size_t pos_ = 0;
};

template <typename T>
T read_little_endian(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof value);
    return value;
}

// A dtype string: byte order ('<' little, '>' big, '|' not applicable, '=' native: little on
// every machine this builds for), kind ('f' float, 'i' signed, 'u' unsigned) and item size.
struct NpyType {
    char kind = 'f';
    std::size_t size = 4;
    bool big_endian = false;
};

NpyType parse_dtype(const std::string& descr, const std::string& path) {
    const auto unsupported = [&] {
        return read_error(path, "NPY dtype '" + descr +
                                    "' is not supported (float32/64, int8-64 or uint8-64, either byte order)");
    };
    if (descr.size() != 3 || std::string_view("<>|=").find(descr[0]) == std::string_view::npos) throw unsupported();
    NpyType type{descr[1], static_cast<std::size_t>(descr[2] - '0'), descr[0] == '>'};
    const bool integer = (type.kind == 'i' || type.kind == 'u') &&
                         (type.size == 1 || type.size == 2 || type.size == 4 || type.size == 8);
    const bool floating = type.kind == 'f' && (type.size == 4 || type.size == 8);
    if (!integer && !floating) throw unsupported();
    return type;
}

template <typename T>
double decode_as(const unsigned char* bytes, bool big_endian) {
    unsigned char ordered[sizeof(T)];
    for (std::size_t k = 0; k < sizeof(T); ++k) ordered[k] = bytes[big_endian ? sizeof(T) - 1 - k : k];
    T value;
    std::memcpy(&value, ordered, sizeof value);
    return static_cast<double>(value);
}

double decode(const unsigned char* bytes, const NpyType& type) {
    switch (type.kind) {
        case 'f': return type.size == 4 ? decode_as<float>(bytes, type.big_endian) : decode_as<double>(bytes, type.big_endian);
        case 'i':
            switch (type.size) {
                case 1: return decode_as<std::int8_t>(bytes, false);
                case 2: return decode_as<std::int16_t>(bytes, type.big_endian);
                case 4: return decode_as<std::int32_t>(bytes, type.big_endian);
                default: return decode_as<std::int64_t>(bytes, type.big_endian);
            }
        default:
            switch (type.size) {
                case 1: return decode_as<std::uint8_t>(bytes, false);
                case 2: return decode_as<std::uint16_t>(bytes, type.big_endian);
                case 4: return decode_as<std::uint32_t>(bytes, type.big_endian);
                default: return decode_as<std::uint64_t>(bytes, type.big_endian);
            }
    }
}

// Reads the items in file order, in slices so that a huge file never needs a second full-size
// buffer; a Fortran-order array (column-major) is transposed on the way into map rows.
void convert_heights(std::ifstream& in, const NpyType& type, bool fortran_order, const HeightConversion& conversion,
                     Heightfield& field, const std::string& path) {
    constexpr std::size_t kSliceItems = 1 << 20;
    std::vector<unsigned char> slice(kSliceItems * type.size);
    const std::size_t rows = static_cast<std::size_t>(field.rows), cols = static_cast<std::size_t>(field.cols);
    for (std::size_t begin = 0; begin < field.size(); begin += kSliceItems) {
        const std::size_t count = std::min(kSliceItems, field.size() - begin);
        in.read(reinterpret_cast<char*>(slice.data()), static_cast<std::streamsize>(count * type.size));
        if (!in) throw read_error(path, "NPY data is truncated");
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t n = begin + i;
            const std::size_t at = fortran_order ? (n % rows) * cols + n / rows : n;
            field.heights_um[at] = conversion.to_um(decode(&slice[i * type.size], type));
        }
    }
}

}  // namespace

Heightfield read_npy(const std::string& path, const LoadOptions& options) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw read_error(path, "cannot open the file");
    in.seekg(0, std::ios::end);
    const auto file_size = static_cast<unsigned long long>(in.tellg());
    in.seekg(0);

    unsigned char preamble[12] = {};
    in.read(reinterpret_cast<char*>(preamble), 8);
    if (!in || std::memcmp(preamble, kMagic, kMagicSize) != 0) throw read_error(path, "not an NPY file (bad magic)");
    const int major = preamble[6];
    if (major < 1 || major > 3)
        throw read_error(path, "NPY format version " + std::to_string(major) + " is not supported");
    const std::size_t length_bytes = major == 1 ? 2 : 4;
    in.read(reinterpret_cast<char*>(preamble + 8), static_cast<std::streamsize>(length_bytes));
    if (!in) throw read_error(path, "NPY header is truncated");
    const unsigned long long header_length =
        major == 1 ? read_little_endian<std::uint16_t>(preamble + 8) : read_little_endian<std::uint32_t>(preamble + 8);
    const unsigned long long data_offset = 8 + length_bytes + header_length;
    if (data_offset > file_size) throw read_error(path, "NPY header is truncated");

    std::string header_text(header_length, '\0');
    in.read(header_text.data(), static_cast<std::streamsize>(header_length));
    const NpyHeader header = HeaderParser(header_text, path).parse();
    const NpyType type = parse_dtype(header.descr, path);
    const std::size_t item = type.size;
    if (header.shape.size() != 2)
        throw read_error(path, "NPY array has " + std::to_string(header.shape.size()) +
                                   " dimensions; a heightfield needs 2 (rows, cols)");
    const long long rows = header.shape[0];
    const long long cols = header.shape[1];
    check_grid_size(cols, rows, path);
    const unsigned long long data_bytes = static_cast<unsigned long long>(rows * cols) * item;
    if (file_size - data_offset < data_bytes)
        throw read_error(path, "NPY data is truncated (" + std::to_string(file_size - data_offset) + " of " +
                                   std::to_string(data_bytes) + " bytes)");
    if (file_size - data_offset > data_bytes)
        throw read_error(path, "NPY file has " + std::to_string(file_size - data_offset - data_bytes) +
                                   " bytes after the array data");

    const HeightConversion conversion = resolve_units({}, options, path);
    Heightfield field = make_heightfield(static_cast<int>(rows), static_cast<int>(cols), conversion.texel_um);
    field.units_assumed = conversion.units_assumed;
    apply_spacing(field, options, conversion.texel_um, {}, path);  // NPY states no spacing
    convert_heights(in, type, header.fortran_order, conversion, field, path);
    return field;
}

void write_npy(const std::string& file, const std::string& path, const Heightfield& field) {
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(field.rows) + ", " +
                         std::to_string(field.cols) + "), }";
    // Version 1.0: the header, padded with spaces and ended by '\n', makes the data start at a
    // multiple of 64 bytes.
    const std::size_t unpadded = kMagicSize + 2 + 2 + header.size() + 1;
    header.append((64 - unpadded % 64) % 64, ' ');
    header += '\n';
    const auto header_length = static_cast<std::uint16_t>(header.size());

    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (!out) throw write_error(path, "cannot create the file");
    out.write(kMagic, kMagicSize);
    const char version[2] = {1, 0};
    out.write(version, 2);
    out.write(reinterpret_cast<const char*>(&header_length), 2);
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(reinterpret_cast<const char*>(field.heights_um.data()),
              static_cast<std::streamsize>(field.size() * sizeof(float)));
    out.close();
    if (!out) throw write_error(path, "writing the NPY data failed (disk full?)");
}

}  // namespace glintscope
