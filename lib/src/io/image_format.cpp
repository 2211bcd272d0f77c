// Heightfields in images, through OpenImageIO (EXR, TIFF, PNG and anything else it reads).
//
// One channel holds the heights: LoadOptions::channel by name or index, else Z, Y, R or the
// first. Image row 0 (the top) is heightfield row 0 (the largest y), so the picture of a file
// and every image glintscope draws of it look the same.
//
// Integer pixels are taken at their stored values, not normalised to [0, 1]: a 16-bit PNG holds
// heights 0..65535 in the height unit (µm unless --height-unit says otherwise), so a file
// quantised in nanometre steps loads with --height-unit nm and nothing else. Normalising would
// tie the heights to the bit depth, which says nothing about the surface.
//
// EXR files written here hold one full-float channel "Z" in µm and header attributes
// glintscope:texel_um and glintscope:height_unit (shortest round-trip decimal text) and
// glintscope:provenance:<key> for each provenance entry; reading them back restores all of it.
// A field with rectangular texels also carries glintscope:texel_y_um (dy; texel_um is dx) and
// the standard PixelAspectRatio dx/dy, so that viewers draw its pixels at their true shape.
// Images without these attributes have no units (units_assumed unless the options give them).
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <cstdint>
#include <cstdio>
#include <string_view>
#include <type_traits>
#include <vector>

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include "formats.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kSamplesPerChunk = std::size_t{1} << 16;
constexpr std::string_view kTexelAttribute = "glintscope:texel_um";
constexpr std::string_view kTexelYAttribute = "glintscope:texel_y_um";
constexpr std::string_view kHeightUnitAttribute = "glintscope:height_unit";
constexpr std::string_view kProvenancePrefix = "glintscope:provenance:";

// OpenImageIO's messages may span lines (one per failed strip); errors are one line, so keep
// the first.
std::string one_line(const std::string& text) {
    const std::size_t start = text.find_first_not_of("\r\n ");
    if (start == std::string::npos) return "unknown error";
    const std::size_t end = text.find_first_of("\r\n", start);
    const std::string first = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    return end == std::string::npos || text.find_first_not_of("\r\n ", end) == std::string::npos ? first
                                                                                                 : first + " ...";
}

std::string channel_list(const OIIO::ImageSpec& spec) {
    std::string list;
    for (int c = 0; c < spec.nchannels; ++c) {
        if (c > 0) list += ", ";
        list += std::to_string(c) + ":" + std::string(spec.channel_name(c));
    }
    return list;
}

int choose_channel(const OIIO::ImageSpec& spec, const std::string& requested, const std::string& path) {
    if (requested.empty()) {
        for (const char* name : {"Z", "Y", "R"})
            if (const int c = spec.channelindex(name); c >= 0) return c;
        return 0;
    }
    if (const int c = spec.channelindex(requested); c >= 0) return c;
    int index = -1;
    const auto [end, ec] = std::from_chars(requested.data(), requested.data() + requested.size(), index);
    if (ec == std::errc() && end == requested.data() + requested.size() && index >= 0 && index < spec.nchannels)
        return index;
    throw read_error(path, "no channel '" + requested + "' (available: " + channel_list(spec) + ")");
}

// A length attribute (shortest round-trip text), absent when the header lacks it.
std::optional<double> header_length(const OIIO::ImageSpec& spec, std::string_view name, const std::string& path) {
    const OIIO::ParamValue* attribute = spec.find_attribute(name, OIIO::TypeDesc::STRING);
    if (!attribute) return std::nullopt;
    const std::string text = attribute->get_string();
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size())
        throw read_error(path, "invalid " + std::string(name) + " '" + text + "' in the header");
    return value;
}

StoredUnits header_units(const OIIO::ImageSpec& spec, const std::string& path) {
    StoredUnits units;
    units.texel_um = header_length(spec, kTexelAttribute, path);
    if (const OIIO::ParamValue* unit = spec.find_attribute(kHeightUnitAttribute, OIIO::TypeDesc::STRING)) {
        try {
            units.height_unit = parse_length_unit(unit->get_string());
        } catch (const Error& e) {
            throw read_error(path, std::string(kHeightUnitAttribute) + " in the header: " + e.what());
        }
    }
    return units;
}

Provenance header_provenance(const OIIO::ImageSpec& spec) {
    Provenance provenance;
    for (const OIIO::ParamValue& attribute : spec.extra_attribs) {
        const std::string& name = attribute.name().string();
        if (name.starts_with(kProvenancePrefix) && attribute.type() == OIIO::TypeDesc::STRING)
            provenance[name.substr(kProvenancePrefix.size())] = attribute.get_string();
    }
    return provenance;
}

// An uncompressed scanline EXR of one full-float channel (what glintscope writes) stores each row
// as the heights' own little-endian bytes: copied straight in, row by row, from OpenEXR's raw
// blocks. Through OpenImageIO, OpenEXR converts them one sample at a time, a function call per
// float (0.8 s of CPU for 8192², 14% of `info`). False (nothing read) for any other layout.
bool read_raw_exr_floats(const std::string& path, Heightfield& field) {
    if constexpr (std::endian::native != std::endian::little) return false;
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const Imf::ChannelList& channels = header.channels();
    const auto channel = channels.begin();
    auto second = channel;
    if (channel != channels.end()) ++second;
    if (header.compression() != Imf::NO_COMPRESSION || header.hasTileDescription() || channel == channels.end() ||
        second != channels.end() || channel.channel().type != Imf::FLOAT ||
        channel.channel().xSampling != 1 || channel.channel().ySampling != 1 ||
        window.max.x - window.min.x + 1 != field.cols || window.max.y - window.min.y + 1 != field.rows)
        return false;
    const std::size_t row_bytes = sizeof(float) * static_cast<std::size_t>(field.cols);
    for (int r = 0; r < field.rows; ++r) {
        const char* data = nullptr;
        int bytes = 0;
        file.rawPixelData(window.min.y + r, data, bytes);
        if (bytes < 0 || static_cast<std::size_t>(bytes) != row_bytes)
            throw read_error(path, "the image data is corrupt (row " + std::to_string(r) + " holds " +
                                       std::to_string(bytes) + " bytes, not " + std::to_string(row_bytes) + ")");
        std::memcpy(field.heights_um.data() + static_cast<std::size_t>(r) * field.cols, data, row_bytes);
    }
    return true;
}

// OpenImageIO's read of one channel, or the raw copy above where it applies.
bool read_stored(OIIO::ImageInput& input, int channel, OIIO::TypeDesc type, void* stored, Heightfield& field,
                 const std::string& path) {
    if (type == OIIO::TypeDesc::FLOAT && input.spec().nchannels == 1 && std::string(input.format_name()) == "openexr") {
        try {
            if (read_raw_exr_floats(path, field)) return true;
        } catch (const Error&) {
            throw;
        } catch (const std::exception& e) {
            throw read_error(path, "the image data is corrupt or truncated (" + one_line(e.what()) + ")");
        }
    }
    return input.read_image(0, 0, channel, channel + 1, type, stored);
}

// Reads the channel in its own integer or float type: asking OpenImageIO for float would
// normalise integers to [0, 1].
template <typename Stored>
void read_channel(OIIO::ImageInput& input, int channel, OIIO::TypeDesc type, const HeightConversion& conversion,
                  Heightfield& field, const std::string& path) {
    // Floats are read straight into the heights and converted in place: no second copy of a
    // large field.
    std::vector<Stored> copy;
    Stored* stored = nullptr;
    if constexpr (std::is_same_v<Stored, float>) {
        stored = field.heights_um.data();
    } else {
        copy.resize(field.size());
        stored = copy.data();
    }
    // Some readers (TIFF) report unreadable strips only as error text and fill them with zeros.
    const bool read = read_stored(input, channel, type, stored, field, path);
    const std::string problem = input.geterror();
    if (!read || !problem.empty())
        throw read_error(path, "the image data is corrupt or truncated (" + one_line(problem) + ")");
    parallel_for(field.size(), kSamplesPerChunk, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) field.heights_um[i] = conversion.to_um(stored[i]);
    });
}

void read_pixels(OIIO::ImageInput& input, int channel, const HeightConversion& conversion, Heightfield& field,
                 const std::string& path) {
    using OIIO::TypeDesc;
    const TypeDesc format = input.spec().channelformat(channel);
    switch (format.basetype) {
        case TypeDesc::UINT8:
            return read_channel<std::uint8_t>(input, channel, TypeDesc::UINT8, conversion, field, path);
        case TypeDesc::INT8: return read_channel<std::int8_t>(input, channel, TypeDesc::INT8, conversion, field, path);
        case TypeDesc::UINT16:
            return read_channel<std::uint16_t>(input, channel, TypeDesc::UINT16, conversion, field, path);
        case TypeDesc::INT16:
            return read_channel<std::int16_t>(input, channel, TypeDesc::INT16, conversion, field, path);
        case TypeDesc::UINT32:
            return read_channel<std::uint32_t>(input, channel, TypeDesc::UINT32, conversion, field, path);
        case TypeDesc::INT32:
            return read_channel<std::int32_t>(input, channel, TypeDesc::INT32, conversion, field, path);
        case TypeDesc::HALF:
        case TypeDesc::FLOAT: return read_channel<float>(input, channel, TypeDesc::FLOAT, conversion, field, path);
        case TypeDesc::DOUBLE: return read_channel<double>(input, channel, TypeDesc::DOUBLE, conversion, field, path);
        default: throw read_error(path, "unsupported pixel type " + std::string(format.c_str()));
    }
}

}  // namespace

// libpng (through OpenImageIO) prints its own "libpng error: ..." lines on stderr beside the one
// line this tool reports, so the image library's reads run with stderr pointed at /dev/null.
// Heightfields are read before any worker thread starts, so nothing else writes meanwhile.
class QuietLibraryOutput {
public:
    QuietLibraryOutput() {
        std::fflush(stderr);
        saved_ = ::dup(STDERR_FILENO);
        const int null = ::open("/dev/null", O_WRONLY);
        if (saved_ >= 0 && null >= 0) ::dup2(null, STDERR_FILENO);
        if (null >= 0) ::close(null);
    }
    ~QuietLibraryOutput() {
        std::fflush(stderr);
        if (saved_ >= 0) {
            ::dup2(saved_, STDERR_FILENO);
            ::close(saved_);
        }
    }
    QuietLibraryOutput(const QuietLibraryOutput&) = delete;
    QuietLibraryOutput& operator=(const QuietLibraryOutput&) = delete;

private:
    int saved_ = -1;
};

// Lossless codecs (deflate, PIZ, RLE) stay below about 1032:1; a header that claims more decoded
// bytes than that from its file, beyond a small size, is a decompression bomb: refuse it before
// the decoder allocates (a PNG claiming 40000² otherwise takes ~20 s and 9 GB, a 6 KB one
// claiming 16384² 1.4 GB). Only the near-constant images of codecs that pack tighter (LZW
// TIFF, up to about 1365:1) and decode to more than 16 MB are refused wrongly.
constexpr double kMaxCompressionRatio = 1100.0;
constexpr double kAlwaysAllowedBytes = 16.0 * (1 << 20);

void check_decoded_size(const OIIO::ImageSpec& spec, const std::string& path) {
    const double decoded = double(spec.width) * spec.height * spec.nchannels * double(spec.format.size());
    std::error_code ec;
    const double stored = double(std::filesystem::file_size(path, ec));
    if (ec || decoded <= kAlwaysAllowedBytes || decoded <= kMaxCompressionRatio * stored) return;
    throw read_error(path, "the header claims " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                               " pixels (" + shortest_text(std::round(decoded / 1e8) / 10.0) + " GB decoded) from a " +
                               shortest_text(std::round(stored / 1e2) / 10.0) +
                               " KB file, more than any lossless compression gives: refused");
}

// OpenEXR allocates each header attribute at the size the header claims before reading it, so
// a few bytes claiming a 2 GB attribute cost 2 GB. The header is a list of attributes (name,
// type name, 4-byte size, value) ended by an empty name, one header per part in multi-part
// files (a further empty name ends the list): every size is checked against the bytes the file
// has left.
std::string read_exr_name(std::istream& in) {
    std::string name;
    for (char ch; in.get(ch) && ch != '\0';)
        if (name.size() < 256) name += ch;
    return name;
}

void check_exr_attribute_sizes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char start[8] = {};
    if (!in.read(reinterpret_cast<char*>(start), sizeof start)) return;
    if (start[0] != 0x76 || start[1] != 0x2f || start[2] != 0x31 || start[3] != 0x01) return;
    const bool multi_part = start[5] & 0x10;
    std::error_code ec;
    const auto file_bytes = static_cast<long long>(std::filesystem::file_size(path, ec));
    if (ec) return;
    for (bool first_attribute = true; in;) {
        const std::string name = read_exr_name(in);
        if (name.empty()) {
            if (!multi_part || first_attribute) return;  // the end of the (last) header
            first_attribute = true;
            continue;
        }
        first_attribute = false;
        read_exr_name(in);  // the type name
        unsigned char size_bytes[4] = {};
        if (!in.read(reinterpret_cast<char*>(size_bytes), 4)) return;
        const std::int32_t size = static_cast<std::int32_t>(std::uint32_t(size_bytes[0]) | std::uint32_t(size_bytes[1]) << 8 |
                                                            std::uint32_t(size_bytes[2]) << 16 |
                                                            std::uint32_t(size_bytes[3]) << 24);
        const long long left = file_bytes - static_cast<long long>(in.tellg());
        if (size < 0 || size > left)
            throw read_error(path, "the EXR header attribute '" + name + "' claims " + std::to_string(size) +
                                       " bytes, but the file has " + std::to_string(left) + " left: refused");
        in.seekg(size, std::ios::cur);
    }
}

Heightfield read_image(const std::string& path, const LoadOptions& options) {
    check_exr_attribute_sizes(path);
    const QuietLibraryOutput quiet;
    // Keep colour channels as stored: associating alpha would scale heights by it.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto input = OIIO::ImageInput::open(path, &config);
    if (!input) throw read_error(path, "not a readable image (" + one_line(OIIO::geterror()) + ")");
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.depth > 1) throw read_error(path, "volume images are not supported");
    if (spec.nchannels <= 0) throw read_error(path, "the image has no channels");
    check_grid_size(spec.width, spec.height, path);
    check_decoded_size(spec, path);
    const int channel = choose_channel(spec, options.channel, path);
    const HeightConversion conversion = resolve_units(header_units(spec, path), options, path);

    Heightfield field = make_heightfield(spec.height, spec.width, conversion.texel_um);
    field.units_assumed = conversion.units_assumed;
    field.provenance = header_provenance(spec);
    // glintscope's EXR states dy only when it differs from dx.
    const std::optional<double> stored_dx = header_length(spec, kTexelAttribute, path);
    const std::optional<double> stored_dy = header_length(spec, kTexelYAttribute, path);
    apply_spacing(field, options, conversion.texel_um, {stored_dx, stored_dy ? stored_dy : stored_dx, 0.0}, path);
    read_pixels(*input, channel, conversion, field, path);
    return field;
}

void write_exr(const std::string& file, const std::string& path, const Heightfield& field) {
    OIIO::ImageSpec spec(field.cols, field.rows, 1, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"Z"};
    // Uncompressed: zip saves ~3% on rough float heights but makes an 8192² write take ~8 s
    // and a read twice as long (measured with OpenImageIO 2.4 on 2 cores).
    spec.attribute("compression", "none");
    spec.attribute(kTexelAttribute, shortest_text(field.dx_um()));
    if (!field.square_texels()) {
        spec.attribute(kTexelYAttribute, shortest_text(field.dy_um()));
        spec.attribute("PixelAspectRatio", static_cast<float>(field.dx_um() / field.dy_um()));
    }
    spec.attribute(kHeightUnitAttribute, to_string(LengthUnit::um));
    for (const auto& [key, value] : field.provenance) spec.attribute(std::string(kProvenancePrefix) + key, value);

    auto output = OIIO::ImageOutput::create(file);
    if (!output) throw write_error(path, "OpenImageIO cannot write EXR (" + one_line(OIIO::geterror()) + ")");
    if (!output->open(file, spec) || !output->write_image(OIIO::TypeDesc::FLOAT, field.heights_um.data()) ||
        !output->close())
        throw write_error(path, one_line(output->geterror()));
}

}  // namespace glintscope
