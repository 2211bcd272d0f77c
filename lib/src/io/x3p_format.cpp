// ISO 25178-72 (formerly ISO 5436-2) X3P files: a zip archive holding main.xml, which
// describes the axes and the grid, and bindata/data.bin with the heights.
//
// Reading: Record1 gives the axes. CX and CY are incremental (AxisType I, Increment in metres)
// or absolute (A: every point stores its coordinate, read as incremental when the coordinates
// form a regular grid, refused naming the point that does not); each absolute axis's DataType
// I/L/F/D means little-endian int16/int32/float32/float64. Integer values are
// Offset + Increment·value (metres); float values are metres and ignore Increment (tools such as
// x3ptools write Increment 1e-6 beside float data in metres). Increment and Offset are optional
// and an empty element means absent. Record3's MatrixDimension gives SizeX, SizeY (SizeZ must
// be 1); the points run X fastest, then Y, either in bindata/data.bin (each point the values of
// its absolute axes in the order X, Y, Z) or listed in main.xml (DataList: one Datum per point,
// the values separated by ';', an empty Datum for an invalid point). NaN in float data and a 0
// bit in the optional bindata/valid.bin (one bit per point, least significant bit first,
// 1 = valid) mark missing points. Every member's claimed size is checked against its packed
// size before it is read.
// main.xml may sit at the archive root or in one top-level folder (as in x3ptools' files).
//
// Orientation: X3P point (i, j) lies at x = i·dx, y = j·dy in the right-handed frame with z up,
// so X3P's first row (j = 0) is the smallest y. Our map-view row 0 is the largest y, so point
// (i, j) becomes heightfield sample (row SizeY − 1 − j, col i): a ramp rising in +y in the X3P
// file rises in +y in the heightfield and towards the top of every image. Some tools store a
// picture's top row first instead (x3ptools' CSAFE logo example reads upside down here) and
// Gwyddion draws X3P's first row at the top; glintscope keeps the standard's right-handed frame.
//
// Writing: float64 heights in metres (every float32 height in µm survives h/1e6·1e6 exactly,
// the round trip is bit-exact), increments printed so that the texel in µm parses back to the
// same double, NaN for missing points plus a valid.bin when any are missing, MD5 checksums of
// main.xml (md5checksum.hex) and of the binary files, and the provenance in Record2's Comment;
// Record2 keeps the instrument of a scan read from X3P (add_record2). main.xml is valid under
// openGPS's ISO5436_2.xsd (tests/lib/io/x3p_schema_test.cpp restates both of its revisions).
// The main.xml checksum is not verified on reading: it is often stale in real files (the
// CSAFE example's is), and the zip CRCs already catch corrupted data.
#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <limits>
#include <list>
#include <optional>
#include <regex>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include <pugixml.hpp>
#include <zip.h>

#include "formats.hpp"
#include "core/md5.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/version.hpp"

namespace glintscope {
namespace {

static_assert(std::endian::native == std::endian::little, "the X3P reader and writer assume a little-endian host");

constexpr std::size_t kMaxXmlBytes = std::size_t{64} << 20;
constexpr double kMaxDeflateRatio = 1032.0;
constexpr const char* kProvenanceMarker = "glintscope provenance";

std::string zip_error_text(int code) {
    zip_error_t error;
    zip_error_init_with_code(&error, code);
    std::string text = zip_error_strerror(&error);
    zip_error_fini(&error);
    return text;
}

// A decimal number of metres as µm, by shifting its decimal exponent instead of multiplying by
// 1e6: "6.45e-07" parses exactly as "6.45e-01" would, so spacings written by
// metres_text() come back as the identical double.
std::optional<double> metres_text_to_um(std::string_view text) {
    text = trim(text);
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    const std::size_t e = text.find_first_of("eE");
    const std::string_view mantissa = text.substr(0, e);
    int exponent = 0;
    if (e != std::string_view::npos) {
        std::string_view exponent_text = text.substr(e + 1);
        if (!exponent_text.empty() && exponent_text.front() == '+') exponent_text.remove_prefix(1);
        const auto [end, ec] =
            std::from_chars(exponent_text.data(), exponent_text.data() + exponent_text.size(), exponent);
        if (ec != std::errc() || end != exponent_text.data() + exponent_text.size() || std::abs(exponent) > 1000)
            return std::nullopt;
    }
    if (mantissa.empty() || mantissa.find_first_not_of("-.0123456789") != std::string_view::npos) return std::nullopt;
    const std::string shifted = std::string(mantissa) + "e" + std::to_string(exponent + 6);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(shifted.data(), shifted.data() + shifted.size(), value);
    if (ec != std::errc() || end != shifted.data() + shifted.size() || !std::isfinite(value)) return std::nullopt;
    return value;
}

// µm as the shortest decimal text in metres that metres_text_to_um() maps back to `um`.
std::string metres_text(double um) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, um, std::chars_format::scientific);
    const std::string_view text(buffer, static_cast<std::size_t>(result.ptr - buffer));
    const std::size_t e = text.find('e');
    int exponent = 0;
    std::from_chars(text.data() + e + 1 + (text[e + 1] == '+'), text.data() + text.size(), exponent);
    return std::string(text.substr(0, e)) + "e" + std::to_string(exponent - 6);
}

// Provenance travels in Record2's Comment as one "key<TAB>value" line per entry after a
// marker line; backslash, tab, line breaks and other control characters are escaped.
std::string escape(const std::string& text) {
    std::string escaped;
    for (unsigned char ch : text) {
        if (ch == '\\')
            escaped += "\\\\";
        else if (ch == '\t')
            escaped += "\\t";
        else if (ch == '\n')
            escaped += "\\n";
        else if (ch < 0x20 || ch == 0x7f) {
            char code[8];
            std::snprintf(code, sizeof code, "\\x%02x", ch);
            escaped += code;
        } else
            escaped += static_cast<char>(ch);
    }
    return escaped;
}

std::string unescape(std::string_view text) {
    std::string plain;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\\' || i + 1 == text.size()) {
            plain += text[i];
            continue;
        }
        const char code = text[++i];
        if (code == 't')
            plain += '\t';
        else if (code == 'n')
            plain += '\n';
        else if (code == 'x' && i + 2 < text.size() && std::isxdigit(static_cast<unsigned char>(text[i + 1])) &&
                 std::isxdigit(static_cast<unsigned char>(text[i + 2]))) {
            unsigned value = 0;
            std::from_chars(text.data() + i + 1, text.data() + i + 3, value, 16);
            plain += static_cast<char>(value);
            i += 2;
        } else
            plain += code;
    }
    return plain;
}

// Where a foreign file's Record2 elements are kept in the provenance (read_provenance) and
// written back from (add_record2).
constexpr std::pair<const char*, const char*> kInstrumentKeys[] = {{"Manufacturer", "x3p:instrument.manufacturer"},
                                                                   {"Model", "x3p:instrument.model"},
                                                                   {"Serial", "x3p:instrument.serial"},
                                                                   {"Version", "x3p:instrument.version"}};
constexpr const char* kCreatorKey = "x3p:creator";
constexpr const char* kCalibrationDateKey = "x3p:calibration_date";
constexpr const char* kProbingTypeKey = "x3p:probing_system.type";
constexpr const char* kProbingIdentificationKey = "x3p:probing_system.identification";

std::string provenance_comment(const Provenance& provenance) {
    std::string comment = std::string(kProvenanceMarker) + " (key<TAB>value per line)";
    for (const auto& [key, value] : provenance) {
        comment += '\n';
        comment += escape(key);
        comment += '\t';
        comment += escape(value);
    }
    return comment;
}

std::optional<Provenance> parse_provenance_comment(std::string_view comment) {
    if (comment.substr(0, std::strlen(kProvenanceMarker)) != kProvenanceMarker) return std::nullopt;
    Provenance provenance;
    std::size_t line_start = comment.find('\n');
    while (line_start != std::string_view::npos) {
        const std::size_t line_end = comment.find('\n', line_start + 1);
        const std::string_view line = comment.substr(line_start + 1, line_end - line_start - 1);
        const std::size_t tab = line.find('\t');
        if (tab != std::string_view::npos) provenance[unescape(line.substr(0, tab))] = unescape(line.substr(tab + 1));
        line_start = line_end;
    }
    return provenance;
}

// ---- reading ----

class ZipReader {
public:
    explicit ZipReader(const std::string& path) : path_(path) {
        int code = 0;
        archive_ = zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &code);
        if (!archive_) throw read_error(path, "not a valid X3P file (zip archive: " + zip_error_text(code) + ")");
    }
    ~ZipReader() { zip_discard(archive_); }
    ZipReader(const ZipReader&) = delete;
    ZipReader& operator=(const ZipReader&) = delete;

    std::optional<zip_uint64_t> locate(const std::string& name) const {
        const zip_int64_t index = zip_name_locate(archive_, name.c_str(), 0);
        if (index < 0) return std::nullopt;
        return static_cast<zip_uint64_t>(index);
    }

    // main.xml at the root, or in a single top-level folder; returns that folder ("" or "dir/").
    std::string main_xml_folder() const {
        if (locate("main.xml")) return "";
        const zip_int64_t count = zip_get_num_entries(archive_, 0);
        for (zip_int64_t i = 0; i < count; ++i) {
            const char* name = zip_get_name(archive_, static_cast<zip_uint64_t>(i), 0);
            if (!name) continue;
            const std::string_view entry(name);
            const std::size_t slash = entry.find('/');
            if (slash != std::string_view::npos && slash > 0 && entry.substr(slash + 1) == "main.xml")
                return std::string(entry.substr(0, slash + 1));
        }
        throw read_error(path_, "not a valid X3P file (the archive has no main.xml)");
    }

    // Members other than `used` (and folders): annotation images, operating-system litter.
    std::vector<std::string> other_members(const std::vector<std::string>& used) const {
        std::vector<std::string> others;
        const zip_int64_t count = zip_get_num_entries(archive_, 0);
        for (zip_int64_t i = 0; i < count; ++i) {
            const char* name = zip_get_name(archive_, static_cast<zip_uint64_t>(i), 0);
            if (!name || std::string_view(name).ends_with('/')) continue;
            if (std::find(used.begin(), used.end(), name) == used.end()) others.emplace_back(name);
        }
        return others;
    }

    // The unpacked size the archive claims for a member, checked against what its packed bytes
    // can hold before anything is allocated for it: deflate expands at most 1032:1 (RFC 1951's
    // longest match, 258 bytes, from a 2-bit code at best), a stored member not at all.
    zip_uint64_t size_of(zip_uint64_t index, const std::string& name) const {
        zip_stat_t stat;
        zip_stat_init(&stat);
        if (zip_stat_index(archive_, index, 0, &stat) != 0 || !(stat.valid & ZIP_STAT_SIZE) ||
            !(stat.valid & ZIP_STAT_COMP_SIZE) || !(stat.valid & ZIP_STAT_COMP_METHOD))
            throw read_error(path_, "cannot read the size of " + name + " in the archive");
        std::error_code ec;
        const auto file_bytes = std::filesystem::file_size(path_, ec);
        if (ec || stat.comp_size > file_bytes)
            throw read_error(path_, name + " claims " + std::to_string(stat.comp_size) + " packed bytes in a " +
                                        std::to_string(file_bytes) + "-byte file: refused");
        const bool stored = stat.comp_method == ZIP_CM_STORE;
        const double most = stored ? double(stat.comp_size) : kMaxDeflateRatio * double(stat.comp_size) + 64.0;
        if (double(stat.size) > most)
            throw read_error(path_, name + " claims " + std::to_string(stat.size) + " bytes unpacked from " +
                                        std::to_string(stat.comp_size) + " packed bytes, more than " +
                                        (stored ? "storing" : "deflate") + " can give: refused");
        return stat.size;
    }

    std::string read(zip_uint64_t index, zip_uint64_t size, const std::string& name) const {
        zip_file_t* file = zip_fopen_index(archive_, index, 0);
        if (!file) throw read_error(path_, "cannot open " + name + " in the archive: " + zip_strerror(archive_));
        std::string bytes(size, '\0');
        zip_uint64_t done = 0;
        while (done < size) {
            const zip_int64_t n = zip_fread(file, bytes.data() + done, size - done);
            if (n < 0) {
                const std::string problem = zip_file_strerror(file);
                zip_fclose(file);
                throw read_error(path_, name + " is corrupt (" + problem + ")");
            }
            if (n == 0) break;
            done += static_cast<zip_uint64_t>(n);
        }
        zip_fclose(file);
        if (done != size) throw read_error(path_, name + " is truncated");
        return bytes;
    }

private:
    std::string path_;
    zip_t* archive_ = nullptr;
};

std::string_view local_name(const pugi::xml_node& node) {
    const std::string_view name = node.name();
    const std::size_t colon = name.find(':');
    return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

// Children are matched by local name, so prefixed and unprefixed documents both read.
pugi::xml_node child(const pugi::xml_node& parent, std::string_view name) {
    for (pugi::xml_node node = parent.first_child(); node; node = node.next_sibling())
        if (node.type() == pugi::node_element && local_name(node) == name) return node;
    return {};
}

class X3pDocument {
public:
    X3pDocument(const std::string& xml, const std::string& path) : path_(path) {
        const pugi::xml_parse_result result = document_.load_buffer(xml.data(), xml.size());
        if (!result)
            throw read_error(path, std::string("main.xml is not valid XML (") + result.description() + " at byte " +
                                       std::to_string(result.offset) + ")");
        root_ = document_.document_element();
        // With or without a namespace prefix; some writers use the standard's old name ISO5436.
        if (local_name(root_) != "ISO5436_2" && local_name(root_) != "ISO5436")
            throw read_error(
                path, "main.xml is not an ISO 5436-2 document (root element '" + std::string(root_.name()) + "')");
    }

    pugi::xml_node root() const { return root_; }

    pugi::xml_node require(const pugi::xml_node& parent, std::string_view name, const std::string& where) const {
        const pugi::xml_node node = child(parent, name);
        if (!node) throw read_error(path_, "main.xml lacks " + where + "/" + std::string(name));
        return node;
    }

    std::string_view require_text(const pugi::xml_node& parent, std::string_view name, const std::string& where) const {
        return require(parent, name, where).child_value();
    }

    Error invalid(const std::string& where, std::string_view text) const {
        return read_error(path_, "main.xml has an invalid " + where + " '" + std::string(trim(text)) + "'");
    }

    // The text of `where` as a finite number (text_format.hpp), or the invalid() error.
    double number(const std::string& where, std::string_view text) const {
        try {
            return parse_number(text);
        } catch (const Error&) {
            throw invalid(where, text);
        }
    }

    // The text of `where` as a whole number from 0 up, or the invalid() error.
    long long count(const std::string& where, std::string_view text) const {
        try {
            return parse_integer(text, 0, std::numeric_limits<long long>::max());
        } catch (const Error&) {
            throw invalid(where, text);
        }
    }

private:
    std::string path_;
    pugi::xml_document document_;
    pugi::xml_node root_;
};

enum class ZType { int16, int32, float32, float64 };

std::size_t byte_size(ZType type) {
    switch (type) {
        case ZType::int16: return 2;
        case ZType::int32: return 4;
        case ZType::float32: return 4;
        case ZType::float64: return 8;
    }
    return 8;
}

// One of Record1's axes. An absolute axis (A) stores a value per point, scaled as
// Offset + Increment·value for the integer types and taken as metres for the float types; an
// incremental axis (I) stores nothing and places point k at Offset + k·Increment.
struct X3pAxis {
    bool absolute = false;
    ZType type = ZType::float64;
    double increment_m = 1.0;
    double offset_m = 0.0;
    std::optional<double> increment_um;  // the incremental axes' spacing, parsed exactly
};

struct X3pLayout {
    long long size_x = 0;
    long long size_y = 0;
    X3pAxis x;
    X3pAxis y;
    X3pAxis z;
    std::string data_link;   // empty when the points are listed in main.xml (DataList)
    std::string valid_link;
    pugi::xml_node data_list;
};

// The standard makes Increment and Offset optional; writers also leave them present but empty
// (x3ptools writes <Offset/>), which means the same as absent.
std::optional<std::string_view> optional_text(const pugi::xml_node& parent, std::string_view name) {
    const std::string_view text = trim(child(parent, name).child_value());
    if (text.empty()) return std::nullopt;
    return text;
}

ZType parse_data_type(const X3pDocument& doc, const pugi::xml_node& axis, const std::string& where) {
    const std::string_view data_type = trim(doc.require_text(axis, "DataType", where));
    if (data_type == "I") return ZType::int16;
    if (data_type == "L") return ZType::int32;
    if (data_type == "F") return ZType::float32;
    if (data_type == "D") return ZType::float64;
    throw doc.invalid(where + "/DataType", data_type);
}

X3pAxis parse_axis(const X3pDocument& doc, const pugi::xml_node& axes, std::string_view name) {
    const std::string where = "Record1/Axes/" + std::string(name);
    const pugi::xml_node node = doc.require(axes, name, "Record1/Axes");
    X3pAxis axis;
    const std::string_view type = trim(doc.require_text(node, "AxisType", where));
    if (type != "I" && type != "A") throw doc.invalid(where + "/AxisType", type);
    axis.absolute = type == "A";
    if (const auto increment = optional_text(node, "Increment")) {
        const double value = doc.number(where + "/Increment", *increment);
        if (value == 0.0) throw doc.invalid(where + "/Increment", *increment);
        axis.increment_m = value;
        if (!axis.absolute) {
            axis.increment_um = metres_text_to_um(*increment);
            if (!axis.increment_um || !(*axis.increment_um > 0.0)) throw doc.invalid(where + "/Increment", *increment);
        }
    }
    if (const auto offset = optional_text(node, "Offset")) axis.offset_m = doc.number(where + "/Offset", *offset);
    // An incremental axis needs no DataType; an absolute one says how its values are stored.
    if (axis.absolute) axis.type = parse_data_type(doc, node, where);
    return axis;
}

X3pLayout parse_layout(const X3pDocument& doc, const std::string& path) {
    X3pLayout layout;
    const pugi::xml_node record1 = doc.require(doc.root(), "Record1", "ISO5436_2");
    const pugi::xml_node axes = doc.require(record1, "Axes", "Record1");
    layout.x = parse_axis(doc, axes, "CX");
    layout.y = parse_axis(doc, axes, "CY");
    layout.z = parse_axis(doc, axes, "CZ");
    if (!layout.z.absolute) throw read_error(path, "X3P CZ axis is incremental (I); heights need an absolute axis");
    for (const auto& [axis, name] : {std::pair{&layout.x, "CX"}, std::pair{&layout.y, "CY"}})
        if (!axis->absolute && !axis->increment_um)
            throw read_error(path, std::string("main.xml gives incremental axis ") + name +
                                       " no Increment, so its spacing is unknown");

    const pugi::xml_node record3 = doc.require(doc.root(), "Record3", "ISO5436_2");
    const pugi::xml_node matrix = child(record3, "MatrixDimension");
    if (!matrix) throw read_error(path, "X3P point lists (no Record3/MatrixDimension) are not supported");
    auto size = [&](std::string_view name) {
        return doc.count("Record3/MatrixDimension/" + std::string(name),
                         doc.require_text(matrix, name, "Record3/MatrixDimension"));
    };
    layout.size_x = size("SizeX");
    layout.size_y = size("SizeY");
    const long long size_z = size("SizeZ");
    if (size_z != 1)
        throw read_error(path, "X3P files with SizeZ = " + std::to_string(size_z) + " layers are not supported");

    if (const pugi::xml_node data_link = child(record3, "DataLink")) {
        layout.data_link = trim(doc.require_text(data_link, "PointDataLink", "Record3/DataLink"));
        if (const auto valid = optional_text(data_link, "ValidPointsLink")) layout.valid_link = *valid;
    } else if (const pugi::xml_node data_list = child(record3, "DataList")) {
        layout.data_list = data_list;
    } else {
        throw read_error(path, "main.xml has neither Record3/DataLink nor Record3/DataList");
    }
    return layout;
}

// Foreign files keep Record2's description of the measurement, each element under its own key
// (the writer puts them back: a converted scan still names what measured it) and the
// instrument's name in one line for `info`; our own files restore their provenance from it.
Provenance read_provenance(const X3pDocument& doc) {
    const pugi::xml_node record2 = child(doc.root(), "Record2");
    if (!record2) return {};
    const std::string_view comment = child(record2, "Comment").child_value();
    if (auto ours = parse_provenance_comment(comment)) return *ours;
    Provenance provenance;
    // "N/A", as tools write for what they do not know, is absent too.
    auto keep = [&](const std::string& key, std::string_view value) {
        value = trim(value);
        if (!value.empty() && value != "N/A") provenance[key] = std::string(value);
    };
    keep(kCreatorKey, child(record2, "Creator").child_value());
    keep("x3p:date", child(record2, "Date").child_value());
    const pugi::xml_node instrument = child(record2, "Instrument");
    std::string instrument_name;
    for (const char* part : {"Manufacturer", "Model", "Version"}) {
        const std::string_view value = trim(child(instrument, part).child_value());
        if (value.empty() || value == "N/A") continue;
        instrument_name += (instrument_name.empty() ? "" : " ") + std::string(value);
    }
    keep("x3p:instrument", instrument_name);
    for (const auto& [element, key] : kInstrumentKeys) keep(key, child(instrument, element).child_value());
    keep(kCalibrationDateKey, child(record2, "CalibrationDate").child_value());
    const pugi::xml_node probing = child(record2, "ProbingSystem");
    keep(kProbingTypeKey, child(probing, "Type").child_value());
    keep(kProbingIdentificationKey, child(probing, "Identification").child_value());
    keep("x3p:comment", comment);
    return provenance;
}

template <typename Stored>
double stored_value(const char* bytes) {
    Stored value;
    std::memcpy(&value, bytes, sizeof value);
    return static_cast<double>(value);
}

// A stored value in metres: integer types through Offset and Increment, float types as they are
// (x3ptools writes Increment 1e-6 beside float data already in metres).
double axis_metres(const X3pAxis& axis, double stored) {
    const bool integer = axis.type == ZType::int16 || axis.type == ZType::int32;
    return integer ? axis.offset_m + axis.increment_m * stored : stored;
}

double decode(const X3pAxis& axis, const char* bytes) {
    switch (axis.type) {
        case ZType::int16: return axis_metres(axis, stored_value<std::int16_t>(bytes));
        case ZType::int32: return axis_metres(axis, stored_value<std::int32_t>(bytes));
        case ZType::float32: return stored_value<float>(bytes);
        case ZType::float64: return stored_value<double>(bytes);
    }
    return 0.0;
}

std::string read_member(const ZipReader& zip, const std::string& folder, const std::string& link,
                        zip_uint64_t expected_size, const std::string& path) {
    const std::string name = folder + link;
    const auto index = zip.locate(name);
    if (!index) throw read_error(path, "the archive lacks " + link + " named in main.xml");
    const zip_uint64_t size = zip.size_of(*index, link);
    if (size < expected_size)
        throw read_error(path, link + " is truncated (" + std::to_string(size) + " bytes, expected " +
                                   std::to_string(expected_size) + ")");
    if (size > expected_size)
        throw read_error(path, link + " has " + std::to_string(size) + " bytes, expected " +
                                   std::to_string(expected_size) + " for the grid in main.xml");
    return zip.read(*index, size, link);
}

// Every point of the matrix, X fastest: its height in metres (NaN when invalid) and, for
// absolute CX and CY, its coordinates in metres.
struct X3pPoints {
    std::vector<double> x;
    std::vector<double> y;
};

// Point records in bindata: the values of the absolute axes in the order X, Y, Z.
template <typename StoreHeight>
X3pPoints decode_binary(const X3pLayout& layout, const std::string& data, const std::string& valid,
                        std::size_t points, const StoreHeight& store_height) {
    X3pPoints coordinates;
    if (layout.x.absolute) coordinates.x.resize(points);
    if (layout.y.absolute) coordinates.y.resize(points);
    const std::size_t x_bytes = layout.x.absolute ? byte_size(layout.x.type) : 0;
    const std::size_t y_bytes = layout.y.absolute ? byte_size(layout.y.type) : 0;
    const std::size_t record = x_bytes + y_bytes + byte_size(layout.z.type);
    for (std::size_t k = 0; k < points; ++k) {
        const char* bytes = data.data() + k * record;
        if (x_bytes) coordinates.x[k] = decode(layout.x, bytes);
        if (y_bytes) coordinates.y[k] = decode(layout.y, bytes + x_bytes);
        // The mask: one bit per point, least significant first, 1 = valid (ISO 25178-72).
        const bool is_valid = valid.empty() || (static_cast<unsigned char>(valid[k / 8]) >> (k % 8)) & 1u;
        store_height(k, is_valid ? decode(layout.z, bytes + x_bytes + y_bytes) : std::nan(""));
    }
    return coordinates;
}

// Points listed in main.xml (ISO 25178-72's DataList): one Datum per point holding the values of
// the absolute axes separated by ';', an empty Datum for an invalid point.
template <typename StoreHeight>
X3pPoints decode_data_list(const X3pLayout& layout, std::size_t points, const std::string& path,
                           const StoreHeight& store_height) {
    X3pPoints coordinates;
    if (layout.x.absolute) coordinates.x.resize(points);
    if (layout.y.absolute) coordinates.y.resize(points);
    std::vector<const X3pAxis*> stored_axes;
    if (layout.x.absolute) stored_axes.push_back(&layout.x);
    if (layout.y.absolute) stored_axes.push_back(&layout.y);
    stored_axes.push_back(&layout.z);
    std::size_t k = 0;
    for (pugi::xml_node datum = layout.data_list.first_child(); datum; datum = datum.next_sibling()) {
        if (datum.type() != pugi::node_element || local_name(datum) != "Datum") continue;
        if (k == points) break;
        const std::string_view text = trim(datum.child_value());
        if (text.empty()) {
            store_height(k++, std::nan(""));
            continue;
        }
        std::vector<double> values;
        for (std::string_view rest = text; !rest.empty();) {
            const std::size_t separator = rest.find(';');
            const std::string_view field = rest.substr(0, separator);
            try {
                values.push_back(parse_number(field));
            } catch (const Error&) {
                throw read_error(path, "main.xml has an invalid Datum " + std::to_string(k) + " '" + std::string(text) + "'");
            }
            rest = separator == std::string_view::npos ? std::string_view() : rest.substr(separator + 1);
        }
        if (values.size() != stored_axes.size())
            throw read_error(path, "main.xml Datum " + std::to_string(k) + " holds " + std::to_string(values.size()) +
                                       " values, expected " + std::to_string(stored_axes.size()) +
                                       " (one per absolute axis)");
        std::size_t v = 0;
        if (layout.x.absolute) coordinates.x[k] = axis_metres(layout.x, values[v++]);
        if (layout.y.absolute) coordinates.y[k] = axis_metres(layout.y, values[v++]);
        store_height(k++, axis_metres(layout.z, values[v]));
    }
    return coordinates;
}

std::size_t count_data_list(const pugi::xml_node& data_list) {
    std::size_t count = 0;
    for (pugi::xml_node datum = data_list.first_child(); datum; datum = datum.next_sibling())
        if (datum.type() == pugi::node_element && local_name(datum) == "Datum") ++count;
    return count;
}

// Absolute coordinates that form a regular grid: coordinate = c0 + n·spacing for every valid
// point (n its column for CX, its row for CY), each within kGridTolerance of a spacing. Returns
// the spacing in µm (least squares over the valid points) and the largest deviation in
// spacings, or throws naming the point that lies off the grid.
constexpr double kGridTolerance = 0.05;

struct GridFit {
    double spacing_um = 0.0;
    double largest_deviation = 0.0;  // in spacings
};

GridFit grid_from_absolute_axis(const std::vector<double>& coordinate_m, const std::vector<bool>& valid,
                                long long size_x, bool along_x, const char* name, const std::string& path) {
    double count = 0.0, sum_n = 0.0, sum_c = 0.0, sum_nn = 0.0, sum_nc = 0.0;
    long long first_n = -1;
    bool several = false;
    const auto index_of = [&](std::size_t k) {
        return along_x ? static_cast<long long>(k) % size_x : static_cast<long long>(k) / size_x;
    };
    for (std::size_t k = 0; k < coordinate_m.size(); ++k) {
        if (!valid[k]) continue;
        if (!std::isfinite(coordinate_m[k]))
            throw read_error(path, std::string("X3P absolute ") + name + " of valid point " + std::to_string(k) +
                                       " is not a number");
        const double n = static_cast<double>(index_of(k));
        if (first_n < 0) first_n = index_of(k);
        several = several || index_of(k) != first_n;
        count += 1.0;
        sum_n += n;
        sum_c += coordinate_m[k];
        sum_nn += n * n;
        sum_nc += n * coordinate_m[k];
    }
    if (!several)
        throw read_error(path, std::string("X3P absolute ") + name +
                                   " axis: the valid points span one line, so the spacing is unknown");
    const double spacing = (count * sum_nc - sum_n * sum_c) / (count * sum_nn - sum_n * sum_n);
    const double start = (sum_c - spacing * sum_n) / count;
    if (!(spacing > 0.0))
        throw read_error(path, std::string("X3P absolute ") + name +
                                   " axis decreases along the point order; only increasing grids are supported");
    GridFit fit{spacing * 1e6, 0.0};
    for (std::size_t k = 0; k < coordinate_m.size(); ++k) {
        if (!valid[k]) continue;
        const double deviation = std::fabs(coordinate_m[k] - (start + spacing * double(index_of(k)))) / spacing;
        fit.largest_deviation = std::max(fit.largest_deviation, deviation);
        if (deviation > kGridTolerance)
            throw read_error(path, std::string("X3P absolute ") + name + " axis is not a regular grid: point " +
                                       std::to_string(k) + " lies " + shortest_text(std::round(deviation * 1e3) / 1e3) +
                                       " spacings off it (tolerance " + shortest_text(kGridTolerance) + ")");
    }
    return fit;
}

// ---- writing ----

class ZipWriter {
public:
    ZipWriter(const std::string& file, const std::string& path) : path_(path) {
        int code = 0;
        archive_ = zip_open(file.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &code);
        if (!archive_) throw write_error(path, "cannot create the zip archive: " + zip_error_text(code));
    }
    ~ZipWriter() {
        if (archive_) zip_discard(archive_);
    }
    ZipWriter(const ZipWriter&) = delete;
    ZipWriter& operator=(const ZipWriter&) = delete;

    // libzip reads the buffer only at close(), so the writer keeps the contents alive. Float
    // heights barely compress, so the fastest deflate level costs little size and much time.
    void add(const std::string& name, std::string contents) {
        const std::string& kept = contents_.emplace_back(std::move(contents));
        zip_source_t* source = zip_source_buffer(archive_, kept.data(), kept.size(), 0);
        const zip_int64_t index =
            source ? zip_file_add(archive_, name.c_str(), source, ZIP_FL_ENC_UTF_8 | ZIP_FL_OVERWRITE) : -1;
        if (index < 0) {
            if (source) zip_source_free(source);
            throw write_error(path_, "cannot add " + name + " to the archive: " + zip_strerror(archive_));
        }
        zip_set_file_compression(archive_, static_cast<zip_uint64_t>(index), ZIP_CM_DEFLATE, 1);
    }

    void close() {
        if (zip_close(archive_) != 0)
            throw write_error(path_, std::string("writing the archive failed: ") + zip_strerror(archive_));
        archive_ = nullptr;
    }

private:
    std::string path_;
    zip_t* archive_ = nullptr;
    std::list<std::string> contents_;
};

struct StringWriter : pugi::xml_writer {
    std::string text;
    void write(const void* data, std::size_t size) override { text.append(static_cast<const char*>(data), size); }
};

void add_text(pugi::xml_node parent, const char* name, const std::string& text) {
    parent.append_child(name).text().set(text.c_str());
}

void add_axis(pugi::xml_node axes, const char* name, const char* axis_type, const std::string& increment) {
    pugi::xml_node axis = axes.append_child(name);
    add_text(axis, "AxisType", axis_type);
    add_text(axis, "DataType", "D");
    add_text(axis, "Increment", increment);
    add_text(axis, "Offset", "0");
}

std::string utc_now() {
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &utc);
    return buffer;
}

// Whether text is an xsd:dateTime, as Record2's dates must be: [-]YYYY-MM-DDThh:mm:ss[.s][zone].
bool is_xsd_date_time(const std::string& text) {
    static const std::regex date_time(R"(-?\d{4,}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?(Z|[+-]\d{2}:\d{2})?)");
    return std::regex_match(text, date_time);
}

// Record2 describes the measurement. A scan read from another X3P keeps its creator,
// instrument, calibration date and probing system (read_provenance), so that a converted scan
// still names what measured it, and its calibration date only when it is an xsd:dateTime (the
// schema's 2020 revision makes it optional; inventing one would misstate the calibration);
// anything else was made by software: glintscope, probing system "Software" (ISO 25178-72's
// value for simulated data, in the schema's 2020 revision). glintscope's own record goes to the
// Comment, which our reader restores the provenance from.
void add_record2(pugi::xml_node root, const Provenance& provenance) {
    const auto kept = [&](const char* key) {
        const auto found = provenance.find(key);
        return found == provenance.end() ? std::string() : found->second;
    };
    // A type of the schema's enumeration says the provenance holds another file's Record2.
    const std::string type = kept(kProbingTypeKey);
    const bool foreign = type == "Contacting" || type == "NonContacting" || type == "Software";
    const std::string now = utc_now();
    pugi::xml_node record2 = root.append_child("Record2");
    add_text(record2, "Date", now);
    const std::string creator = foreign ? kept(kCreatorKey) : "glintscope";
    if (!creator.empty()) add_text(record2, "Creator", creator);
    pugi::xml_node instrument = record2.append_child("Instrument");
    const std::string ours[] = {"N/A", "glintscope", "N/A", version()};
    for (int k = 0; k < 4; ++k) {
        const std::string value = foreign ? kept(kInstrumentKeys[k].second) : ours[k];
        add_text(instrument, kInstrumentKeys[k].first, value.empty() ? "N/A" : value);
    }
    const std::string calibration = foreign ? kept(kCalibrationDateKey) : now;
    if (is_xsd_date_time(calibration)) add_text(record2, "CalibrationDate", calibration);
    pugi::xml_node probing = record2.append_child("ProbingSystem");
    add_text(probing, "Type", foreign ? type : "Software");
    const std::string identification = foreign ? kept(kProbingIdentificationKey) : "glintscope";
    add_text(probing, "Identification", identification.empty() ? "N/A" : identification);
    add_text(record2, "Comment", provenance_comment(provenance));
}

std::string main_xml(const Heightfield& field, const std::string& data_md5, const std::string& valid_md5) {
    pugi::xml_document doc;
    pugi::xml_node declaration = doc.append_child(pugi::node_declaration);
    declaration.append_attribute("version") = "1.0";
    declaration.append_attribute("encoding") = "UTF-8";
    pugi::xml_node root = doc.append_child("p:ISO5436_2");
    root.append_attribute("xmlns:p") = "http://www.opengps.eu/2008/ISO5436_2";
    root.append_attribute("xmlns:xsi") = "http://www.w3.org/2001/XMLSchema-instance";
    root.append_attribute("xsi:schemaLocation") =
        "http://www.opengps.eu/2008/ISO5436_2 http://www.opengps.eu/2008/ISO5436_2/ISO5436_2.xsd";

    pugi::xml_node record1 = root.append_child("Record1");
    add_text(record1, "Revision", "ISO5436 - 2000");
    add_text(record1, "FeatureType", "SUR");
    pugi::xml_node axes = record1.append_child("Axes");
    add_axis(axes, "CX", "I", metres_text(field.dx_um()));
    add_axis(axes, "CY", "I", metres_text(field.dy_um()));
    add_axis(axes, "CZ", "A", "1");

    add_record2(root, field.provenance);

    pugi::xml_node record3 = root.append_child("Record3");
    pugi::xml_node matrix = record3.append_child("MatrixDimension");
    add_text(matrix, "SizeX", std::to_string(field.cols));
    add_text(matrix, "SizeY", std::to_string(field.rows));
    add_text(matrix, "SizeZ", "1");
    pugi::xml_node data_link = record3.append_child("DataLink");
    add_text(data_link, "PointDataLink", "bindata/data.bin");
    add_text(data_link, "MD5ChecksumPointData", data_md5);
    if (!valid_md5.empty()) {
        add_text(data_link, "ValidPointsLink", "bindata/valid.bin");
        add_text(data_link, "MD5ChecksumValidPoints", valid_md5);
    }
    add_text(root.append_child("Record4"), "ChecksumFile", "md5checksum.hex");

    StringWriter writer;
    doc.save(writer, "  ", pugi::format_default, pugi::encoding_utf8);
    return writer.text;
}

}  // namespace

Heightfield read_x3p(const std::string& path, const LoadOptions& options) {
    const ZipReader zip(path);
    const std::string folder = zip.main_xml_folder();
    const zip_uint64_t xml_index = *zip.locate(folder + "main.xml");
    const zip_uint64_t xml_size = zip.size_of(xml_index, "main.xml");
    if (xml_size == 0) throw read_error(path, "main.xml is empty");
    if (xml_size > kMaxXmlBytes) throw read_error(path, "main.xml is implausibly large");
    const X3pDocument doc(zip.read(xml_index, xml_size, "main.xml"), path);
    const X3pLayout layout = parse_layout(doc, path);
    check_grid_size(layout.size_x, layout.size_y, path);
    const auto points = static_cast<std::size_t>(layout.size_x * layout.size_y);

    // The data's size is checked against the grid before the grid is allocated.
    const bool listed = layout.data_link.empty();
    std::string data, valid;
    if (listed) {
        if (const std::size_t count = count_data_list(layout.data_list); count != points)
            throw read_error(path, "main.xml's DataList holds " + std::to_string(count) + " points, expected " +
                                       std::to_string(points) + " for the grid in main.xml");
    } else {
        const std::size_t record = (layout.x.absolute ? byte_size(layout.x.type) : 0) +
                                   (layout.y.absolute ? byte_size(layout.y.type) : 0) + byte_size(layout.z.type);
        data = read_member(zip, folder, layout.data_link, points * record, path);
        if (!layout.valid_link.empty()) valid = read_member(zip, folder, layout.valid_link, (points + 7) / 8, path);
    }
    const auto decode_points = [&](const auto& store_height) {
        return listed ? decode_data_list(layout, points, path, store_height)
                      : decode_binary(layout, data, valid, points, store_height);
    };

    Provenance notes;
    std::optional<double> dx_um = layout.x.increment_um;
    std::optional<double> dy_um = layout.y.increment_um;
    double square_tolerance = 1e-6;
    if (layout.x.absolute || layout.y.absolute) {
        std::vector<bool> valid_points(points);
        const X3pPoints coordinates =
            decode_points([&](std::size_t k, double metres) { valid_points[k] = !std::isnan(metres); });
        std::string note;
        for (const auto& [axis, name, along_x] : {std::tuple{&layout.x, "CX", true}, std::tuple{&layout.y, "CY", false}}) {
            if (!axis->absolute) continue;
            const GridFit fit = grid_from_absolute_axis(along_x ? coordinates.x : coordinates.y, valid_points,
                                                        layout.size_x, along_x, name, path);
            (along_x ? dx_um : dy_um) = fit.spacing_um;
            note += std::string(note.empty() ? "" : "; ") + name + " absolute, read as a regular grid of spacing " +
                    format_length(fit.spacing_um) + " (largest deviation " +
                    shortest_text(std::round(fit.largest_deviation * 1e4) / 1e4) + " spacings)";
        }
        notes["x3p:axes"] = note;
        // Spacings fitted from stored coordinates agree only to the coordinates' precision.
        square_tolerance = 1e-4;
    }
    if (listed) notes["x3p:points"] = "listed in main.xml (Record3/DataList)";

    StoredUnits stored;
    stored.texel_um = dx_um;
    stored.height_unit = LengthUnit::m;
    const HeightConversion conversion = resolve_units(stored, options, path);

    const int rows = static_cast<int>(layout.size_y);
    const int cols = static_cast<int>(layout.size_x);
    Heightfield field = make_heightfield(rows, cols, conversion.texel_um);
    field.units_assumed = conversion.units_assumed;
    field.provenance = read_provenance(doc);
    field.provenance.insert(notes.begin(), notes.end());
    // Annotation masks (PNG layers some tools add) have no meaning the standard fixes: not read,
    // but named, so that `info` tells the user what was left aside.
    std::vector<std::string> used = {folder + "main.xml", folder + "md5checksum.hex"};
    if (!listed) used.push_back(folder + layout.data_link);
    if (!layout.valid_link.empty()) used.push_back(folder + layout.valid_link);
    if (const std::vector<std::string> others = zip.other_members(used); !others.empty())
        field.provenance["x3p:not_read"] = join(others);
    decode_points([&](std::size_t k, double metres) {
        const auto j = static_cast<int>(k / cols);
        const auto i = static_cast<int>(k % cols);
        field.at(rows - 1 - j, i) = std::isnan(metres) ? std::numeric_limits<float>::quiet_NaN() : conversion.to_um(metres);
    });
    // Spacings that differ beyond what the file can state are kept as they are (rectangular texels).
    apply_spacing(field, options, conversion.texel_um, {dx_um, dy_um, square_tolerance}, path);
    return field;
}

void write_x3p(const std::string& file, const std::string& path, const Heightfield& field) {
    const int rows = field.rows;
    const int cols = field.cols;
    std::string data(field.size() * sizeof(double), '\0');
    std::string valid;
    const bool has_missing = count_missing(field) > 0;
    if (has_missing) valid.assign((field.size() + 7) / 8, '\0');
    for (int j = 0; j < rows; ++j) {
        for (int i = 0; i < cols; ++i) {
            const std::size_t index = static_cast<std::size_t>(j) * cols + i;
            const float height_um = field.at(rows - 1 - j, i);
            const double height_m = static_cast<double>(height_um) / 1e6;
            std::memcpy(data.data() + index * sizeof(double), &height_m, sizeof height_m);
            if (has_missing && !std::isnan(height_um))
                valid[index / 8] = static_cast<char>(valid[index / 8] | (1u << (index % 8)));
        }
    }
    const std::string data_md5 = md5_hex(data.data(), data.size());
    const std::string valid_md5 = has_missing ? md5_hex(valid.data(), valid.size()) : std::string();
    std::string xml = main_xml(field, data_md5, valid_md5);
    const std::string checksum = md5_hex(xml.data(), xml.size()) + " *main.xml\n";

    ZipWriter zip(file, path);
    zip.add("main.xml", std::move(xml));
    zip.add("bindata/data.bin", std::move(data));
    if (has_missing) zip.add("bindata/valid.bin", std::move(valid));
    zip.add("md5checksum.hex", checksum);
    zip.close();
}

}  // namespace glintscope
