// ISO 25178-72 (formerly ISO 5436-2) X3P files: a zip archive holding main.xml, which
// describes the axes and the grid, and bindata/data.bin with the heights.
//
// Reading: Record1 gives the axes. CX and CY must be incremental (AxisType I) with their
// Increment in metres; CZ's DataType I/L/F/D means little-endian int16/int32/float32/float64.
// For the integer types a height is Offset + Increment·value (metres); float types hold metres
// directly and ignore CZ's Increment (tools such as x3ptools write Increment 1e-6 beside float
// data in metres). Record3's MatrixDimension gives SizeX, SizeY (SizeZ must be 1); the points
// run X fastest, then Y. NaN in float data and a 0 bit in the optional bindata/valid.bin
// (one bit per point, least significant bit first, 1 = valid) mark missing points.
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
// main.xml (md5checksum.hex) and of the binary files, and the provenance in Record2's Comment.
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
#include <limits>
#include <list>
#include <optional>
#include <string>
#include <string_view>

#include <pugixml.hpp>
#include <zip.h>

#include "formats.hpp"
#include "core/md5.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

static_assert(std::endian::native == std::endian::little, "the X3P reader and writer assume a little-endian host");

constexpr std::size_t kMaxXmlBytes = std::size_t{64} << 20;
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

    zip_uint64_t size_of(zip_uint64_t index, const std::string& name) const {
        zip_stat_t stat;
        zip_stat_init(&stat);
        if (zip_stat_index(archive_, index, 0, &stat) != 0 || !(stat.valid & ZIP_STAT_SIZE))
            throw read_error(path_, "cannot read the size of " + name + " in the archive");
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

struct X3pLayout {
    long long size_x = 0;
    long long size_y = 0;
    std::optional<double> dx_um;
    std::optional<double> dy_um;
    ZType z_type = ZType::float64;
    double z_increment_m = 1.0;
    double z_offset_m = 0.0;
    std::string data_link;
    std::string valid_link;
};

std::optional<double> axis_spacing_um(const X3pDocument& doc, const pugi::xml_node& axes, std::string_view name,
                                      const std::string& path) {
    const std::string where = "Record1/Axes/" + std::string(name);
    const pugi::xml_node axis = doc.require(axes, name, "Record1/Axes");
    const std::string_view type = trim(doc.require_text(axis, "AxisType", where));
    if (type != "I")
        throw read_error(path, "X3P " + std::string(name) + " axis is of type '" + std::string(type) +
                                   "'; only incremental (I) x and y axes are supported");
    const std::string_view increment = doc.require_text(axis, "Increment", where);
    const std::optional<double> um = metres_text_to_um(increment);
    if (!um || !(*um > 0.0)) throw doc.invalid(where + "/Increment", increment);
    return um;
}

X3pLayout parse_layout(const X3pDocument& doc, const std::string& path) {
    X3pLayout layout;
    const pugi::xml_node record1 = doc.require(doc.root(), "Record1", "ISO5436_2");
    const pugi::xml_node axes = doc.require(record1, "Axes", "Record1");
    layout.dx_um = axis_spacing_um(doc, axes, "CX", path);
    layout.dy_um = axis_spacing_um(doc, axes, "CY", path);

    const pugi::xml_node cz = doc.require(axes, "CZ", "Record1/Axes");
    const std::string_view data_type = trim(doc.require_text(cz, "DataType", "Record1/Axes/CZ"));
    if (data_type == "I")
        layout.z_type = ZType::int16;
    else if (data_type == "L")
        layout.z_type = ZType::int32;
    else if (data_type == "F")
        layout.z_type = ZType::float32;
    else if (data_type == "D")
        layout.z_type = ZType::float64;
    else
        throw doc.invalid("Record1/Axes/CZ/DataType", data_type);
    if (const pugi::xml_node increment = child(cz, "Increment")) {
        layout.z_increment_m = doc.number("Record1/Axes/CZ/Increment", increment.child_value());
        if (layout.z_increment_m == 0.0) throw doc.invalid("Record1/Axes/CZ/Increment", increment.child_value());
    }
    if (const pugi::xml_node offset = child(cz, "Offset"))
        layout.z_offset_m = doc.number("Record1/Axes/CZ/Offset", offset.child_value());

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

    const pugi::xml_node data_link = child(record3, "DataLink");
    if (!data_link) throw read_error(path, "X3P point data inside main.xml (no Record3/DataLink) is not supported");
    layout.data_link = trim(doc.require_text(data_link, "PointDataLink", "Record3/DataLink"));
    if (const pugi::xml_node valid = child(data_link, "ValidPointsLink")) layout.valid_link = trim(valid.child_value());
    return layout;
}

// Foreign files keep Record2's description; our own files restore their provenance from it.
Provenance read_provenance(const X3pDocument& doc) {
    const pugi::xml_node record2 = child(doc.root(), "Record2");
    if (!record2) return {};
    const std::string_view comment = child(record2, "Comment").child_value();
    if (auto ours = parse_provenance_comment(comment)) return *ours;
    Provenance provenance;
    auto keep = [&](const std::string& key, std::string_view value) {
        value = trim(value);
        if (!value.empty()) provenance[key] = std::string(value);
    };
    keep("x3p:creator", child(record2, "Creator").child_value());
    keep("x3p:date", child(record2, "Date").child_value());
    const pugi::xml_node instrument = child(record2, "Instrument");
    std::string instrument_name;
    for (const char* part : {"Manufacturer", "Model", "Version"}) {
        const std::string_view value = trim(child(instrument, part).child_value());
        if (value.empty() || value == "N/A") continue;
        instrument_name += (instrument_name.empty() ? "" : " ") + std::string(value);
    }
    keep("x3p:instrument", instrument_name);
    keep("x3p:comment", comment);
    return provenance;
}

template <typename Stored>
double stored_value(const char* bytes, std::size_t index) {
    Stored value;
    std::memcpy(&value, bytes + index * sizeof(Stored), sizeof value);
    return static_cast<double>(value);
}

double height_in_metres(const X3pLayout& layout, const std::string& data, std::size_t index) {
    switch (layout.z_type) {
        case ZType::int16:
            return layout.z_offset_m + layout.z_increment_m * stored_value<std::int16_t>(data.data(), index);
        case ZType::int32:
            return layout.z_offset_m + layout.z_increment_m * stored_value<std::int32_t>(data.data(), index);
        case ZType::float32: return stored_value<float>(data.data(), index);
        case ZType::float64: return stored_value<double>(data.data(), index);
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
    const std::string spacing = metres_text(field.texel_um);
    add_axis(axes, "CX", "I", spacing);
    add_axis(axes, "CY", "I", spacing);
    add_axis(axes, "CZ", "A", "1");

    const std::string now = utc_now();
    pugi::xml_node record2 = root.append_child("Record2");
    add_text(record2, "Date", now);
    add_text(record2, "Creator", "glintscope");
    pugi::xml_node instrument = record2.append_child("Instrument");
    add_text(instrument, "Manufacturer", "N/A");
    add_text(instrument, "Model", "glintscope");
    add_text(instrument, "Serial", "N/A");
    add_text(instrument, "Version", "0.1.0");
    add_text(record2, "CalibrationDate", now);
    pugi::xml_node probing = record2.append_child("ProbingSystem");
    add_text(probing, "Type", "Software");
    add_text(probing, "Identification", "glintscope");
    add_text(record2, "Comment", provenance_comment(field.provenance));

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

    StoredUnits stored;
    stored.texel_um = layout.dx_um;
    stored.height_unit = LengthUnit::m;
    if (!options.texel_um && std::fabs(*layout.dx_um - *layout.dy_um) > 1e-6 * *layout.dx_um)
        throw read_error(path, "the sample spacing differs in x (" + format_length(*layout.dx_um) + ") and y (" +
                                   format_length(*layout.dy_um) + "); glintscope needs square texels");
    const HeightConversion conversion = resolve_units(stored, options, path);

    const std::string data = read_member(zip, folder, layout.data_link, points * byte_size(layout.z_type), path);
    const std::string valid =
        layout.valid_link.empty() ? std::string() : read_member(zip, folder, layout.valid_link, (points + 7) / 8, path);

    const int rows = static_cast<int>(layout.size_y);
    const int cols = static_cast<int>(layout.size_x);
    Heightfield field = make_heightfield(rows, cols, conversion.texel_um);
    field.units_assumed = conversion.units_assumed;
    field.provenance = read_provenance(doc);
    // Annotation masks (PNG layers some tools add) have no meaning the standard fixes: not read,
    // but named, so that `info` tells the user what was left aside.
    std::vector<std::string> used = {folder + "main.xml", folder + "md5checksum.hex", folder + layout.data_link};
    if (!layout.valid_link.empty()) used.push_back(folder + layout.valid_link);
    if (const std::vector<std::string> others = zip.other_members(used); !others.empty())
        field.provenance["x3p:not_read"] = join(others);
    for (int j = 0; j < rows; ++j) {
        for (int i = 0; i < cols; ++i) {
            const std::size_t index = static_cast<std::size_t>(j) * cols + i;
            const bool is_valid = valid.empty() || (static_cast<unsigned char>(valid[index / 8]) >> (index % 8)) & 1u;
            field.at(rows - 1 - j, i) = is_valid ? conversion.to_um(height_in_metres(layout, data, index))
                                                 : std::numeric_limits<float>::quiet_NaN();
        }
    }
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
