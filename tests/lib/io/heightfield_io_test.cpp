// Heightfield files: exact round trips through EXR, NPY and X3P, the map-view orientation of
// each format's own layout, the real CSAFE X3P example, and clean errors for bad files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <zip.h>

#include "cli_runner.hpp"
#include "zip_files.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "core/md5.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

LoadOptions options_with(std::string channel, std::optional<LengthUnit> height_unit, std::optional<double> texel_um,
                         double height_scale = 1.0) {
    LoadOptions options;
    options.channel = std::move(channel);
    options.height_unit = height_unit;
    options.texel_um = texel_um;
    options.height_scale = height_scale;
    return options;
}

// Heights using the whole float mantissa and several magnitudes, with a few missing points.
Heightfield awkward_field(int rows, int cols, double texel_um) {
    Heightfield field = make_heightfield(rows, cols, texel_um);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            field.at(r, c) = static_cast<float>(std::sin(0.37 * r + 1.3 * c) * std::pow(10.0, (r + c) % 7 - 3) +
                                                1.0 / (1.0 + r * cols + c));
    field.at(0, 0) = kNaN;
    field.at(rows - 1, cols / 2) = kNaN;
    field.provenance = {{"generator", "test: awkward_field"}, {"note", "tab\there, newline\nthere, back\\slash"}};
    return field;
}

// The same float bit patterns, NaN matching NaN.
void expect_identical_heights(const Heightfield& expected, const Heightfield& actual) {
    ASSERT_EQ(expected.rows, actual.rows);
    ASSERT_EQ(expected.cols, actual.cols);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const float a = expected.heights_um[i];
        const float b = actual.heights_um[i];
        if (std::isnan(a)) {
            EXPECT_TRUE(std::isnan(b)) << "sample " << i;
        } else {
            std::uint32_t bits_a, bits_b;
            std::memcpy(&bits_a, &a, 4);
            std::memcpy(&bits_b, &b, 4);
            EXPECT_EQ(bits_a, bits_b) << "sample " << i << ": " << a << " vs " << b;
        }
    }
}

// ---- helpers for hand-made X3P archives ----

// write_zip fails the test when libzip does.
void write_zip(const std::string& path, const std::vector<std::pair<std::string, std::string>>& members) {
    ASSERT_TRUE(testing::write_zip(path, members)) << path;
}

using testing::read_zip_member;

struct X3pSpec {
    std::string size_x = "4";
    std::string size_y = "3";
    std::string increment = "1e-06";
    std::string data_type = "D";
    std::string z_increment = "1";
    std::string z_offset = "0";
    std::string valid_link;
    bool with_size_x = true;
};

std::string main_xml(const X3pSpec& spec) {
    std::string xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
 <Record1><Revision>ISO5436 - 2000</Revision><FeatureType>SUR</FeatureType><Axes>
  <CX><AxisType>I</AxisType><DataType>D</DataType><Increment>)" +
                      spec.increment + R"(</Increment><Offset>0</Offset></CX>
  <CY><AxisType>I</AxisType><DataType>D</DataType><Increment>)" +
                      spec.increment + R"(</Increment><Offset>0</Offset></CY>
  <CZ><AxisType>A</AxisType><DataType>)" +
                      spec.data_type + "</DataType><Increment>" + spec.z_increment + "</Increment><Offset>" +
                      spec.z_offset + R"(</Offset></CZ>
 </Axes></Record1>
 <Record3><MatrixDimension>)";
    if (spec.with_size_x) xml += "<SizeX>" + spec.size_x + "</SizeX>";
    xml += "<SizeY>" + spec.size_y +
           "</SizeY><SizeZ>1</SizeZ></MatrixDimension>\n  <DataLink><PointDataLink>bindata/data.bin</PointDataLink>";
    if (!spec.valid_link.empty()) xml += "<ValidPointsLink>" + spec.valid_link + "</ValidPointsLink>";
    return xml + "</DataLink></Record3>\n</p:ISO5436_2>\n";
}

template <typename T>
std::string binary(const std::vector<T>& values) {
    return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

void write_file(const std::string& path, const std::string& contents) {
    std::ofstream(path, std::ios::binary) << contents;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string npy_file(const std::string& descr, const std::string& shape, const std::string& data,
                     const std::string& fortran = "False") {
    std::string header = "{'descr': '" + descr + "', 'fortran_order': " + fortran + ", 'shape': " + shape + ", }";
    header.append((64 - (10 + header.size() + 1) % 64) % 64, ' ');
    header += '\n';
    const auto length = static_cast<std::uint16_t>(header.size());
    return std::string("\x93NUMPY\x01\x00", 8) + std::string(reinterpret_cast<const char*>(&length), 2) + header + data;
}

// The message of the Error load_heightfield throws, which must be one line naming the file.
std::string load_error(const std::string& path, const LoadOptions& options = {}) {
    try {
        load_heightfield(path, options);
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(path), std::string::npos) << message;
        return message;
    }
    ADD_FAILURE() << "no error loading " << path;
    return {};
}

// ---- round trips ----

class RoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(RoundTrip, HeightsAreBitExactAndMetadataSurvives) {
    TemporaryDirectory directory;
    const std::string path = directory.file("field." + GetParam());
    const Heightfield original = awkward_field(37, 53, 0.3141592653589793);
    save_heightfield(path, original);
    LoadOptions options;
    if (GetParam() == "npy") options.texel_um = original.texel_um;  // NPY has nowhere to keep units
    const Heightfield loaded = load_heightfield(path, options);

    expect_identical_heights(original, loaded);
    EXPECT_EQ(loaded.texel_um, original.texel_um);
    EXPECT_EQ(count_missing(loaded), 2u);
    if (GetParam() == "npy") {
        EXPECT_TRUE(loaded.units_assumed);  // the heights' unit is still a guess
    } else {
        EXPECT_FALSE(loaded.units_assumed);
        EXPECT_EQ(loaded.provenance, original.provenance);
    }
}

// A 2:1 field (and an awkward ratio) comes back with the same samples and both spacings; NPY keeps
// no spacing at all, so there it is the samples alone (convert says so).
TEST_P(RoundTrip, RectangularTexelsSurviveExactly) {
    TemporaryDirectory directory;
    const std::string path = directory.file("rect." + GetParam());
    for (const auto& [dx, dy] : {std::pair{1.0, 2.0}, std::pair{0.3141592653589793, 0.2718281828459045}}) {
        Heightfield original = awkward_field(9, 14, dx);
        set_spacing(original, dx, dy);
        save_heightfield(path, original);
        const Heightfield loaded = load_heightfield(path);
        expect_identical_heights(original, loaded);
        if (GetParam() == "npy") continue;
        EXPECT_EQ(loaded.dx_um(), dx);
        EXPECT_EQ(loaded.dy_um(), dy);
        EXPECT_EQ(loaded.provenance.count("square_texels"), 0u);
    }
}

TEST_P(RoundTrip, RampInPlusYStaysARampInPlusY) {
    TemporaryDirectory directory;
    const std::string path = directory.file("ramp." + GetParam());
    Heightfield ramp = make_heightfield(5, 4, 2.0);
    for (int r = 0; r < ramp.rows; ++r)
        for (int c = 0; c < ramp.cols; ++c) ramp.at(r, c) = static_cast<float>(sample_position(ramp, r, c).y);
    save_heightfield(path, ramp);
    const Heightfield loaded = load_heightfield(path, options_with("", {}, 2.0));
    for (int r = 0; r < ramp.rows; ++r)
        for (int c = 0; c < ramp.cols; ++c)
            EXPECT_FLOAT_EQ(loaded.at(r, c), sample_position(loaded, r, c).y) << r << "," << c;
}

INSTANTIATE_TEST_SUITE_P(Formats, RoundTrip, ::testing::Values("exr", "npy", "x3p"));

TEST(HeightfieldIo, X3pTexelSizesParseBackToTheSameDouble) {
    TemporaryDirectory directory;
    const std::string path = directory.file("texel.x3p");
    for (double texel : {0.645, 0.1, 1.0 / 3.0, 2.5e-3, 123.456789, 0.30000000000000004, 7.0e-5, 3.3e4,
                         0.6450000000000951, 1.0 / 7.0}) {
        Heightfield field = make_heightfield(2, 3, texel, 1.0f);
        save_heightfield(path, field);
        EXPECT_EQ(load_heightfield(path).texel_um, texel);
    }
}

TEST(HeightfieldIo, X3pChecksumsMatchTheArchivedFiles) {
    TemporaryDirectory directory;
    const std::string path = directory.file("sums.x3p");
    save_heightfield(path, awkward_field(6, 5, 1.0));
    const std::string xml = read_zip_member(path, "main.xml");
    const std::string data = read_zip_member(path, "bindata/data.bin");
    const std::string valid = read_zip_member(path, "bindata/valid.bin");
    EXPECT_EQ(read_zip_member(path, "md5checksum.hex"), md5_hex(xml.data(), xml.size()) + " *main.xml\n");
    EXPECT_NE(xml.find("<MD5ChecksumPointData>" + md5_hex(data.data(), data.size())), std::string::npos);
    EXPECT_NE(xml.find("<MD5ChecksumValidPoints>" + md5_hex(valid.data(), valid.size())), std::string::npos);
    // 30 points, two missing: (row 0, col 0) is X3P point (0, 5) = index 25; (5, 2) is index 2.
    ASSERT_EQ(valid.size(), 4u);
    EXPECT_EQ(static_cast<unsigned char>(valid[0]), 0xfbu);  // bit 2 clear
    EXPECT_EQ(static_cast<unsigned char>(valid[3]), 0x3du);  // bit 25 - 24 = 1 clear, bits 30, 31 unused
}

// ---- each format's own layout ----

TEST(HeightfieldIo, X3pFirstRowIsTheSmallestY) {
    TemporaryDirectory directory;
    Heightfield ramp = make_heightfield(3, 2, 1.0);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 2; ++c) ramp.at(r, c) = static_cast<float>(sample_position(ramp, r, c).y);
    const std::string path = directory.file("ramp.x3p");
    save_heightfield(path, ramp);
    const std::string data = read_zip_member(path, "bindata/data.bin");
    ASSERT_EQ(data.size(), 6 * sizeof(double));
    std::vector<double> metres(6);
    std::memcpy(metres.data(), data.data(), data.size());
    // X fastest, then Y upwards: y = 0.5, 1.5, 2.5 µm.
    const std::vector<double> expected = {0.5e-6, 0.5e-6, 1.5e-6, 1.5e-6, 2.5e-6, 2.5e-6};
    for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(metres[i], expected[i]) << i;
}

TEST(HeightfieldIo, HandMadeX3pRampInJRisesInY) {
    TemporaryDirectory directory;
    const std::string path = directory.file("hand.x3p");
    std::vector<double> metres;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) metres.push_back(1e-6 * (10 * j + i));
    write_zip(path, {{"main.xml", main_xml({})}, {"bindata/data.bin", binary(metres)}});
    const Heightfield field = load_heightfield(path);
    ASSERT_EQ(field.rows, 3);
    ASSERT_EQ(field.cols, 4);
    EXPECT_FLOAT_EQ(field.at(2, 0), 0.0f);  // bottom-left: X3P's first point
    EXPECT_FLOAT_EQ(field.at(2, 3), 3.0f);
    EXPECT_FLOAT_EQ(field.at(0, 1), 21.0f);  // top row: X3P's last row
    EXPECT_EQ(field.texel_um, 1.0);
    EXPECT_FALSE(field.units_assumed);
}

TEST(HeightfieldIo, NpyAndExrRowZeroIsTheTop) {
    TemporaryDirectory directory;
    Heightfield field = make_heightfield(2, 1, 1.0);
    field.at(0, 0) = 7.0f;  // top
    field.at(1, 0) = 3.0f;
    save_heightfield(directory.file("f.npy"), field);
    const std::string npy = read_file(directory.file("f.npy"));
    float first = 0.0f;
    std::memcpy(&first, npy.data() + npy.size() - 8, 4);
    EXPECT_EQ(first, 7.0f);

    save_heightfield(directory.file("f.exr"), field);
    auto input = OIIO::ImageInput::open(directory.file("f.exr"));
    ASSERT_TRUE(input);
    float pixels[2] = {};
    ASSERT_TRUE(input->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, pixels));
    EXPECT_EQ(pixels[0], 7.0f);  // scanline 0, the top of the picture
    EXPECT_EQ(input->spec().channel_name(0), "Z");
    EXPECT_EQ(input->spec().get_string_attribute("glintscope:height_unit"), "um");
}

// ---- the real example ----

TEST(HeightfieldIo, CsafeLogoX3pMatchesItsRawData) {
    const std::string path = testing::shared_path("data/csafe-logo.x3p");
    const Heightfield field = load_heightfield(path);
    ASSERT_EQ(field.cols, 741);
    ASSERT_EQ(field.rows, 419);
    EXPECT_NEAR(field.texel_um, 0.645, 1e-9);
    EXPECT_FALSE(field.units_assumed);
    EXPECT_EQ(count_missing(field), 0u);
    EXPECT_EQ(field.provenance.at("x3p:creator"), "Heike Hofmann, CSAFE");

    const std::string data = read_zip_member(path, "csafe-logo/bindata/data.bin");
    ASSERT_EQ(data.size(), 741u * 419u * 8u);
    EXPECT_EQ(md5_hex(data.data(), data.size()), "021a34716ab08d418048c137dc74f92b");  // from its main.xml
    float lowest = 1e9f, highest = -1e9f;
    for (int j = 0; j < 419; ++j)
        for (int i = 0; i < 741; ++i) {
            double metres = 0.0;
            std::memcpy(&metres, data.data() + (static_cast<std::size_t>(j) * 741 + i) * 8, 8);
            ASSERT_EQ(field.at(418 - j, i), static_cast<float>(metres * 1e6)) << i << "," << j;
            lowest = std::min(lowest, field.at(418 - j, i));
            highest = std::max(highest, field.at(418 - j, i));
        }
    // A logo embossed a fraction of a micrometre: heights 0.21 to 0.83 µm.
    EXPECT_NEAR(lowest, 0.2078, 1e-3);
    EXPECT_NEAR(highest, 0.8275, 1e-3);
}

// ---- X3P variants ----

TEST(HeightfieldIo, X3pNaNsAreMissingPoints) {
    TemporaryDirectory directory;
    const std::string path = directory.file("nan.x3p");
    std::vector<double> metres(12, 2e-6);
    metres[0] = metres[5] = metres[11] = std::numeric_limits<double>::quiet_NaN();
    write_zip(path, {{"main.xml", main_xml({})}, {"bindata/data.bin", binary(metres)}});
    const Heightfield field = load_heightfield(path);
    EXPECT_EQ(count_missing(field), 3u);
    EXPECT_TRUE(std::isnan(field.at(2, 0)));  // point 0 is bottom-left
    EXPECT_TRUE(std::isnan(field.at(1, 1)));  // point 5 = (1, 1)
    EXPECT_TRUE(std::isnan(field.at(0, 3)));  // point 11 = (3, 2) top-right
    EXPECT_FLOAT_EQ(field.at(1, 2), 2.0f);
}

TEST(HeightfieldIo, X3pIntegerHeightsUseIncrementOffsetAndValidMask) {
    TemporaryDirectory directory;
    const std::string path = directory.file("int.x3p");
    X3pSpec spec;
    spec.data_type = "I";
    spec.z_increment = "1e-9";  // nm steps
    spec.z_offset = "5e-7";     // + 0.5 µm
    spec.valid_link = "bindata/valid.bin";
    std::vector<std::int16_t> steps(12);
    for (int i = 0; i < 12; ++i) steps[i] = static_cast<std::int16_t>(100 * i - 300);
    const std::string valid = {static_cast<char>(0xfe), static_cast<char>(0xf7)};  // points 0 and 11 invalid
    write_zip(path, {{"main.xml", main_xml(spec)}, {"bindata/data.bin", binary(steps)}, {"bindata/valid.bin", valid}});
    const Heightfield field = load_heightfield(path);
    EXPECT_EQ(count_missing(field), 2u);
    EXPECT_TRUE(std::isnan(field.at(2, 0)));
    EXPECT_TRUE(std::isnan(field.at(0, 3)));
    EXPECT_FLOAT_EQ(field.at(2, 1), 0.5f - 0.2f);  // point 1: -200 nm + 0.5 µm
    EXPECT_FLOAT_EQ(field.at(0, 0), 0.5f + 0.5f);  // point 8: 500 nm + 0.5 µm
}

TEST(HeightfieldIo, X3pFloatHeightsIgnoreTheZIncrement) {
    TemporaryDirectory directory;
    const std::string path = directory.file("float.x3p");
    X3pSpec spec;
    spec.data_type = "F";
    spec.z_increment = "1e-06";  // as x3ptools writes beside float data in metres
    write_zip(path, {{"main.xml", main_xml(spec)}, {"bindata/data.bin", binary(std::vector<float>(12, 3e-7f))}});
    EXPECT_NEAR(load_heightfield(path).at(0, 0), 0.3f, 1e-6);
}

TEST(HeightfieldIo, X3pInAFolderLikeX3ptoolsWritesIt) {
    TemporaryDirectory directory;
    const std::string path = directory.file("folder.x3p");
    write_zip(path,
              {{"scan/main.xml", main_xml({})}, {"scan/bindata/data.bin", binary(std::vector<double>(12, 1e-6))}});
    EXPECT_FLOAT_EQ(load_heightfield(path).at(1, 1), 1.0f);
}

TEST(HeightfieldIo, X3pVariantsAsWrittenInTheField) {
    // Root without prefix and namespace, or with the standard's old name; the archive with
    // operating-system litter and an annotation image beside the members, all in one folder.
    TemporaryDirectory directory;
    const std::string data = binary(std::vector<double>(12, 2e-6));
    std::string xml = main_xml({});
    for (const auto& [from, to] : {std::pair{std::string("<p:ISO5436_2 xmlns:p=\"http://www.opengps.eu/2008/ISO5436_2\">"),
                                             std::string("<ISO5436_2>")},
                                   std::pair{std::string("</p:ISO5436_2>"), std::string("</ISO5436_2>")}})
        xml.replace(xml.find(from), from.size(), to);
    std::string old_name = xml;
    old_name.replace(old_name.find("<ISO5436_2>"), 11, "<ISO5436>");
    old_name.replace(old_name.find("</ISO5436_2>"), 12, "</ISO5436>");
    const std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> variants = {
        {"plain.x3p", {{"main.xml", xml}, {"bindata/data.bin", data}}},
        {"old.x3p", {{"main.xml", old_name}, {"bindata/data.bin", data}}},
        {"litter.x3p",
         {{"__MACOSX/._main.xml", "junk"}, {"s/.DS_Store", "junk"}, {"s/main.xml", main_xml({})},
          {"s/bindata/data.bin", data}, {"s/annotations/mask.png", "not read"}}}};
    for (const auto& [name, members] : variants) {
        SCOPED_TRACE(name);
        write_zip(directory.file(name), members);
        const Heightfield field = load_heightfield(directory.file(name));
        EXPECT_EQ(field.cols, 4);
        EXPECT_EQ(field.rows, 3);
        EXPECT_EQ(field.texel_um, 1.0);
        EXPECT_FLOAT_EQ(field.at(2, 3), 2.0f);
        if (name == "litter.x3p") {  // what was left aside is named for `info`
            EXPECT_EQ(field.provenance.at("x3p:not_read"), "__MACOSX/._main.xml, s/.DS_Store, s/annotations/mask.png");
        } else {
            EXPECT_EQ(field.provenance.count("x3p:not_read"), 0u);
        }
    }
    std::string wrong = xml;
    wrong.replace(wrong.find("<ISO5436_2>"), 11, "<ISO25178>");
    wrong.replace(wrong.find("</ISO5436_2>"), 12, "</ISO25178>");
    write_zip(directory.file("wrong.x3p"), {{"main.xml", wrong}, {"bindata/data.bin", data}});
    EXPECT_NE(load_error(directory.file("wrong.x3p")).find("root element 'ISO25178'"), std::string::npos);
}

// Instruments' spacings differ in x and y (calibration, line scanners): the reader keeps them
// and the samples as they are; a --texel declares the texels square.
TEST(HeightfieldIo, X3pRectangularSpacingIsKeptAsRead) {
    TemporaryDirectory directory;
    const std::string path = directory.file("rect.x3p");
    std::string xml = main_xml({});
    xml.replace(xml.rfind("<Increment>1e-06"), 16, "<Increment>2e-06");  // CY
    std::vector<double> ramp;  // h = j µm on stored row j (y = (j + ½)·2 µm): linear in y
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) ramp.push_back(j * 1e-6);
    write_zip(path, {{"main.xml", xml}, {"bindata/data.bin", binary(ramp)}});
    const Heightfield field = load_heightfield(path);
    ASSERT_EQ(field.rows, 3);
    ASSERT_EQ(field.cols, 4);
    EXPECT_EQ(field.dx_um(), 1.0);
    EXPECT_DOUBLE_EQ(field.dy_um(), 2.0);
    EXPECT_DOUBLE_EQ(field.height_um(), 6.0);
    for (int j = 0; j < 3; ++j) EXPECT_EQ(field.at(2 - j, 2), static_cast<float>(j)) << j;  // samples untouched
    EXPECT_EQ(field.provenance.count("square_texels"), 0u);
    const Heightfield declared = load_heightfield(path, options_with("", {}, 1.5));
    EXPECT_EQ(declared.texel_um, 1.5);
    EXPECT_TRUE(declared.square_texels());

    xml.replace(xml.rfind("<Increment>2e-06"), 16, "<Increment>2e-05");  // 20:1
    write_zip(path, {{"main.xml", xml}, {"bindata/data.bin", binary(ramp)}});
    EXPECT_NE(load_error(path).find("differ by more than 16 times"), std::string::npos);
}

// ---- images and unit options ----

TEST(HeightfieldIo, Png16HoldsIntegerHeightsInTheChosenUnit) {
    TemporaryDirectory directory;
    const std::string path = directory.file("h.png");
    const std::vector<std::uint16_t> pixels = {0, 1000, 65535, 7, 8, 9};  // 1 x 2 pixels, RGB
    OIIO::ImageSpec spec(1, 2, 3, OIIO::TypeDesc::UINT16);
    auto output = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(output && output->open(path, spec) && output->write_image(OIIO::TypeDesc::UINT16, pixels.data()));
    output->close();

    const Heightfield red = load_heightfield(path);  // default: R
    EXPECT_EQ(red.at(0, 0), 0.0f);
    EXPECT_EQ(red.at(1, 0), 7.0f);
    EXPECT_TRUE(red.units_assumed);
    const Heightfield green_nm = load_heightfield(path, options_with("1", LengthUnit::nm, {}));
    EXPECT_FLOAT_EQ(green_nm.at(0, 0), 1.0f);  // 1000 nm
    const Heightfield blue = load_heightfield(path, options_with("B", {}, 0.5));
    EXPECT_EQ(blue.at(0, 0), 65535.0f);
    EXPECT_EQ(blue.texel_um, 0.5);
    EXPECT_NE(load_error(path, options_with("Z", {}, {})).find("no channel 'Z' (available: 0:R, 1:G, 2:B)"),
              std::string::npos);
}

TEST(HeightfieldIo, HeightsInTexelsScaleWithTheTexelAndHeightScale) {
    TemporaryDirectory directory;
    const std::string path = directory.file("t.npy");
    write_file(path, npy_file("<f8", "(1, 2)", binary(std::vector<double>{2.0, -4.0})));
    const Heightfield field = load_heightfield(path, options_with("", LengthUnit::texel, 0.25, -3.0));
    EXPECT_FALSE(field.units_assumed);
    EXPECT_EQ(field.at(0, 0), -1.5f);  // 2 texels of 0.25 µm, times -3
    EXPECT_EQ(field.at(0, 1), 3.0f);
    EXPECT_NE(load_error(path, options_with("", {}, {}, 0.0)).find("height scale"), std::string::npos);
    EXPECT_NE(load_error(path, options_with("", {}, -1.0)).find("texel size"), std::string::npos);
}

// ---- bad files ----

TEST(HeightfieldIo, MissingAndEmptyFilesOfEveryFormat) {
    TemporaryDirectory directory;
    for (const std::string extension : {"npy", "x3p", "exr", "png", "tif"}) {
        const std::string path = directory.file("empty." + extension);
        EXPECT_NE(load_error(directory.file("absent." + extension)).find("no such file"), std::string::npos);
        write_file(path, "");
        EXPECT_NE(load_error(path).find("the file is empty"), std::string::npos);
    }
}

TEST(HeightfieldIo, TruncatedFilesOfEveryFormat) {
    TemporaryDirectory directory;
    for (const std::string extension : {"npy", "x3p", "exr"}) {
        const std::string path = directory.file("cut." + extension);
        save_heightfield(path, awkward_field(40, 30, 1.0));
        const std::string whole = read_file(path);
        write_file(path, whole.substr(0, whole.size() / 2));
        EXPECT_NE(load_error(path).find("cannot read"), std::string::npos) << extension;
    }
    // glintscope's own EXR (uncompressed float) is copied from OpenEXR's raw rows: a cut one too
    // stops at the first row it lacks.
    EXPECT_NE(load_error(directory.file("cut.exr")).find("corrupt or truncated"), std::string::npos);
    // An uncompressed TIFF cut inside its strips: libtiff reports the lost strips only as error text.
    const std::string tiff = directory.file("cut.tif");
    const std::vector<float> flat(256 * 256, 0.25f);
    OIIO::ImageSpec spec(256, 256, 1, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "none");
    auto output = OIIO::ImageOutput::create(tiff);
    ASSERT_TRUE(output && output->open(tiff, spec) && output->write_image(OIIO::TypeDesc::FLOAT, flat.data()));
    output->close();
    const std::string whole_tiff = read_file(tiff);
    write_file(tiff, whole_tiff.substr(0, whole_tiff.size() / 2));
    EXPECT_NE(load_error(tiff).find("corrupt or truncated"), std::string::npos);

    const std::string npy = directory.file("cut.npy");
    save_heightfield(npy, awkward_field(4, 3, 1.0));
    const std::string whole = read_file(npy);
    write_file(npy, whole.substr(0, whole.size() - 1));
    EXPECT_NE(load_error(npy).find("NPY data is truncated (47 of 48 bytes)"), std::string::npos);
}

TEST(HeightfieldIo, CorruptX3pArchives) {
    TemporaryDirectory directory;
    const std::string path = directory.file("bad.x3p");
    const std::string twelve = binary(std::vector<double>(12, 1e-6));

    write_file(path, "this is not a zip archive");
    EXPECT_NE(load_error(path).find("not a valid X3P file"), std::string::npos);
    write_zip(path, {{"bindata/data.bin", twelve}});
    EXPECT_NE(load_error(path).find("no main.xml"), std::string::npos);
    write_zip(path, {{"main.xml", "<ISO5436_2><Record1>"}, {"bindata/data.bin", twelve}});
    EXPECT_NE(load_error(path).find("not valid XML"), std::string::npos);
    X3pSpec no_size_x;
    no_size_x.with_size_x = false;
    write_zip(path, {{"main.xml", main_xml(no_size_x)}, {"bindata/data.bin", twelve}});
    EXPECT_NE(load_error(path).find("lacks Record3/MatrixDimension/SizeX"), std::string::npos);
    write_zip(path, {{"main.xml", main_xml({})}, {"bindata/data.bin", twelve.substr(0, 90)}});
    EXPECT_NE(load_error(path).find("bindata/data.bin is truncated (90 bytes, expected 96)"), std::string::npos);
    write_zip(path, {{"main.xml", main_xml({})}});
    EXPECT_NE(load_error(path).find("lacks bindata/data.bin"), std::string::npos);
    X3pSpec huge;
    huge.size_x = huge.size_y = "100000000";
    write_zip(path, {{"main.xml", main_xml(huge)}, {"bindata/data.bin", twelve}});
    EXPECT_NE(load_error(path).find("exceeds the limit"), std::string::npos);
    X3pSpec zero;
    zero.size_x = "0";
    write_zip(path, {{"main.xml", main_xml(zero)}, {"bindata/data.bin", ""}});
    EXPECT_NE(load_error(path).find("the grid is empty (0 x 3 samples)"), std::string::npos);
    const auto refusal = [&](const X3pSpec& spec) {  // main.xml of `spec` beside 12 doubles
        write_zip(path, {{"main.xml", main_xml(spec)}, {"bindata/data.bin", twelve}});
        return load_error(path);
    };
    X3pSpec bad;
    bad.size_y = "three";
    EXPECT_NE(refusal(bad).find("invalid Record3/MatrixDimension/SizeY 'three'"), std::string::npos);
    bad = {};
    bad.size_x = "-4";
    EXPECT_NE(refusal(bad).find("invalid Record3/MatrixDimension/SizeX '-4'"), std::string::npos);
    bad = {};
    bad.data_type = "Q";
    EXPECT_NE(refusal(bad).find("invalid Record1/Axes/CZ/DataType 'Q'"), std::string::npos);
    bad = {};
    bad.z_offset = " inf ";
    EXPECT_NE(refusal(bad).find("invalid Record1/Axes/CZ/Offset 'inf'"), std::string::npos);
    bad = {};
    bad.z_increment = "0";
    EXPECT_NE(refusal(bad).find("invalid Record1/Axes/CZ/Increment '0'"), std::string::npos);
    X3pSpec short_mask;
    short_mask.valid_link = "bindata/valid.bin";
    write_zip(path, {{"main.xml", main_xml(short_mask)}, {"bindata/data.bin", twelve}, {"bindata/valid.bin", "\xff"}});
    EXPECT_NE(load_error(path).find("bindata/valid.bin is truncated"), std::string::npos);
}

TEST(HeightfieldIo, CorruptNpyFiles) {
    TemporaryDirectory directory;
    const std::string path = directory.file("bad.npy");
    const std::string six = binary(std::vector<float>(6, 1.0f));
    write_file(path, npy_file("<c8", "(2, 3)", six));
    EXPECT_NE(load_error(path).find("dtype '<c8' is not supported"), std::string::npos);
    write_file(path, npy_file("<f4", "(1, 2, 3)", six));
    EXPECT_NE(load_error(path).find("3 dimensions"), std::string::npos);
    write_file(path, npy_file("<f4", "(6,)", six));
    EXPECT_NE(load_error(path).find("1 dimensions"), std::string::npos);
    write_file(path, npy_file("<f4", "(0, 3)", ""));
    EXPECT_NE(load_error(path).find("the grid is empty"), std::string::npos);
    write_file(path, npy_file("<f4", "(2, 3", six));
    EXPECT_NE(load_error(path).find("corrupt NPY header"), std::string::npos);
    write_file(path, "\x93NUMPX and more bytes");
    EXPECT_NE(load_error(path).find("not an NPY file"), std::string::npos);
    write_file(path, npy_file("<f4", "(2, 3)", six + "xxxx"));
    EXPECT_NE(load_error(path).find("4 bytes after the array data"), std::string::npos);
}

TEST(HeightfieldIo, NaNOnlyDataIsRejectedInEveryFormat) {
    TemporaryDirectory directory;
    Heightfield empty = make_heightfield(3, 4, 1.0, kNaN);
    for (const std::string extension : {"npy", "x3p", "exr"}) {
        const std::string path = directory.file("nan." + extension);
        EXPECT_THROW(save_heightfield(path, empty), Error);  // refused on writing too
        EXPECT_FALSE(std::filesystem::exists(path));
    }
    write_file(directory.file("nan.npy"), npy_file("<f4", "(3, 4)", binary(std::vector<float>(12, kNaN))));
    EXPECT_NE(load_error(directory.file("nan.npy")).find("every height is missing"), std::string::npos);
    write_zip(directory.file("nan.x3p"),
              {{"main.xml", main_xml({})},
               {"bindata/data.bin", binary(std::vector<double>(12, std::numeric_limits<double>::quiet_NaN()))}});
    EXPECT_NE(load_error(directory.file("nan.x3p")).find("every height is missing"), std::string::npos);
}

TEST(HeightfieldIo, GarbageImagesAndUnknownOutputFormats) {
    TemporaryDirectory directory;
    const std::string path = directory.file("noise.png");
    write_file(path, "\x89PNG but not really a PNG file at all");
    EXPECT_NE(load_error(path).find("cannot read"), std::string::npos);
    EXPECT_THROW(save_heightfield(directory.file("field.txt"), awkward_field(3, 3, 1.0)), Error);
    EXPECT_EQ(testing::count_entries(directory.path()), 1);
}

}  // namespace
}  // namespace glintscope
