// X3P in the forms ISO 25178-72 allows and instruments write: empty optional elements, points
// listed in main.xml (DataList), absolute CX and CY axes, the validity mask. Each variant holds
// the same 4 × 3 surface as a plain incremental binary file, so each must load to the same
// heights, spacing and missing points.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "cli_runner.hpp"
#include "zip_files.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/io/heightfield_io.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

constexpr int kSizeX = 4;
constexpr int kSizeY = 3;
constexpr double kSpacingM = 2.5e-6;

// Heights in metres of point k (X fastest); points 2 and 7 are invalid.
double height_m(int k) { return 1e-7 * (k * k - 5 * k + 3); }
bool is_valid(int k) { return k != 2 && k != 7; }

struct Axis {
    std::string type = "I";
    std::string data_type;  // omitted when empty
    std::string increment = "2.5e-06";
    std::string offset = "0";
};

std::string axis_xml(const char* name, const Axis& axis) {
    std::string xml = std::string("<") + name + "><AxisType>" + axis.type + "</AxisType>";
    if (!axis.data_type.empty()) xml += "<DataType>" + axis.data_type + "</DataType>";
    xml += "<Increment>" + axis.increment + "</Increment><Offset>" + axis.offset + "</Offset></" + name + ">";
    return xml;
}

std::string main_xml(const Axis& x, const Axis& y, const Axis& z, const std::string& record3_data) {
    return R"(<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2"><Record1><Revision>ISO5436 - 2000</Revision>
<FeatureType>SUR</FeatureType><Axes>)" +
           axis_xml("CX", x) + axis_xml("CY", y) + axis_xml("CZ", z) +
           "</Axes></Record1><Record3><MatrixDimension><SizeX>" + std::to_string(kSizeX) + "</SizeX><SizeY>" +
           std::to_string(kSizeY) + "</SizeY><SizeZ>1</SizeZ></MatrixDimension>" + record3_data +
           "</Record3></p:ISO5436_2>\n";
}

const std::string kDataOnlyLink = "<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink>";
const std::string kDataLink =
    "<DataLink><PointDataLink>bindata/data.bin</PointDataLink><ValidPointsLink>bindata/valid.bin"
    "</ValidPointsLink></DataLink>";

Axis float64_heights() { return {"A", "D", "1", "0"}; }

template <typename T>
void append(std::string& bytes, T value) {
    bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
}

// bindata/valid.bin for the invalid points 2 and 7: one bit per point, least significant first.
std::string validity_mask() { return {static_cast<char>(0x7b), static_cast<char>(0x0f)}; }

std::string number_text(double value) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.17g", value);
    return buffer;
}

// The reference: incremental axes, float64 heights in bindata with the validity mask.
std::string write_reference(const TemporaryDirectory& directory) {
    std::string data;
    for (int k = 0; k < kSizeX * kSizeY; ++k) append(data, is_valid(k) ? height_m(k) : 0.0);
    const std::string path = directory.file("reference.x3p");
    EXPECT_TRUE(testing::write_zip(path, {{"main.xml", main_xml({}, {}, float64_heights(), kDataLink)},
                                          {"bindata/data.bin", data},
                                          {"bindata/valid.bin", validity_mask()}}));
    return path;
}

void expect_same_field(const Heightfield& expected, const Heightfield& actual) {
    ASSERT_EQ(expected.rows, actual.rows);
    ASSERT_EQ(expected.cols, actual.cols);
    EXPECT_NEAR(actual.texel_um, expected.texel_um, 1e-9);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (std::isnan(expected.heights_um[i]))
            EXPECT_TRUE(std::isnan(actual.heights_um[i])) << i;
        else
            EXPECT_FLOAT_EQ(actual.heights_um[i], expected.heights_um[i]) << i;
    }
}

std::string load_error(const std::string& path) {
    try {
        load_heightfield(path);
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        return message;
    }
    ADD_FAILURE() << "no error loading " << path;
    return {};
}

TEST(X3pVariants, ReferenceHoldsTheSurfaceInMapView) {
    const TemporaryDirectory directory;
    const Heightfield field = load_heightfield(write_reference(directory));
    EXPECT_EQ(field.texel_um, 2.5);
    EXPECT_EQ(count_missing(field), 2u);
    EXPECT_TRUE(std::isnan(field.at(2, 2)));  // point 2 = (2, 0): bottom row
    EXPECT_TRUE(std::isnan(field.at(1, 3)));  // point 7 = (3, 1)
    EXPECT_FLOAT_EQ(field.at(0, 1), static_cast<float>(height_m(9) * 1e6));
}

TEST(X3pVariants, EmptyOptionalElementsReadAsAbsent) {
    // x3ptools writes <Offset/> (or an empty Offset) for CZ: the standard makes it optional.
    const TemporaryDirectory directory;
    const Heightfield reference = load_heightfield(write_reference(directory));
    std::string data;
    for (int k = 0; k < kSizeX * kSizeY; ++k) append(data, is_valid(k) ? height_m(k) : 0.0);
    std::string xml = main_xml({}, {}, {"A", "D", "", ""}, kDataLink);
    const std::string path = directory.file("empty.x3p");
    ASSERT_TRUE(testing::write_zip(
        path, {{"main.xml", xml}, {"bindata/data.bin", data}, {"bindata/valid.bin", validity_mask()}}));
    expect_same_field(reference, load_heightfield(path));

    // Integer heights with no Increment and an empty Offset: stored value × 1 m + 0 (the
    // standard's defaults), here nanometre-valued integers scaled by an explicit Increment.
    std::string steps;
    for (int k = 0; k < kSizeX * kSizeY; ++k)
        append(steps, static_cast<std::int32_t>(std::lround(is_valid(k) ? height_m(k) * 1e9 : 0.0)));
    const std::string integers = directory.file("integers.x3p");
    ASSERT_TRUE(testing::write_zip(integers, {{"main.xml", main_xml({}, {}, {"A", "L", "1e-9", ""}, kDataLink)},
                                              {"bindata/data.bin", steps},
                                              {"bindata/valid.bin", validity_mask()}}));
    expect_same_field(reference, load_heightfield(integers));

    // An incremental axis with an empty Increment has no spacing: refused, naming it.
    const std::string no_spacing = directory.file("no-spacing.x3p");
    ASSERT_TRUE(testing::write_zip(no_spacing, {{"main.xml", main_xml({"I", "", "", ""}, {}, float64_heights(), kDataLink)},
                                                {"bindata/data.bin", data},
                                                {"bindata/valid.bin", validity_mask()}}));
    EXPECT_NE(load_error(no_spacing).find("incremental axis CX no Increment"), std::string::npos);
}

TEST(X3pVariants, PointsListedInMainXmlMatchTheBinaryForm) {
    const TemporaryDirectory directory;
    const Heightfield reference = load_heightfield(write_reference(directory));
    std::string list = "<DataList>";
    for (int k = 0; k < kSizeX * kSizeY; ++k)
        list += is_valid(k) ? "<Datum>" + number_text(height_m(k)) + "</Datum>" : std::string("<Datum/>");
    const std::string path = directory.file("list.x3p");
    ASSERT_TRUE(testing::write_zip(path, {{"main.xml", main_xml({}, {}, float64_heights(), list + "</DataList>")}}));
    const Heightfield listed = load_heightfield(path);
    expect_same_field(reference, listed);
    EXPECT_EQ(listed.provenance.at("x3p:points"), "listed in main.xml (Record3/DataList)");

    // One point short of the grid: refused before anything is allocated for it.
    const std::string short_list = directory.file("short.x3p");
    ASSERT_TRUE(testing::write_zip(
        short_list, {{"main.xml", main_xml({}, {}, float64_heights(), list.substr(0, list.rfind("<Datum")) + "</DataList>")}}));
    EXPECT_NE(load_error(short_list).find("DataList holds 11 points, expected 12"), std::string::npos);
}

// Absolute CX and CY: every point carries its coordinates; `jitter` moves point 5 off the grid
// by that fraction of a spacing.
std::vector<std::pair<double, double>> coordinates(double jitter) {
    std::vector<std::pair<double, double>> xy;
    for (int k = 0; k < kSizeX * kSizeY; ++k)
        xy.emplace_back(1e-3 + (k % kSizeX) * kSpacingM + (k == 5 ? jitter * kSpacingM : 0.0),
                        -2e-3 + (k / kSizeX) * kSpacingM);
    return xy;
}

TEST(X3pVariants, AbsoluteAxesOnARegularGridReadAsIncremental) {
    const TemporaryDirectory directory;
    const Heightfield reference = load_heightfield(write_reference(directory));
    const Axis absolute_x{"A", "D", "1", "0"};
    const Axis absolute_y{"A", "F", "1", "0"};  // float32 y, as coordinates are often stored
    std::string data;
    std::string list = "<DataList>";
    for (int k = 0; k < kSizeX * kSizeY; ++k) {
        const auto [x, y] = coordinates(0.0)[k];
        append(data, x);
        append(data, static_cast<float>(y));
        append(data, is_valid(k) ? height_m(k) : std::numeric_limits<double>::quiet_NaN());
        list += is_valid(k) ? "<Datum>" + number_text(x) + ";" + number_text(y) + ";" + number_text(height_m(k)) +
                                  "</Datum>"
                            : std::string("<Datum/>");
    }
    const std::string binary_path = directory.file("absolute.x3p");
    ASSERT_TRUE(testing::write_zip(binary_path, {{"main.xml", main_xml(absolute_x, absolute_y, float64_heights(), kDataOnlyLink)},
                                                 {"bindata/data.bin", data}}));
    const Heightfield binary = load_heightfield(binary_path);
    expect_same_field(reference, binary);
    EXPECT_NE(binary.provenance.at("x3p:axes").find("CX absolute, read as a regular grid of spacing 2.5 um"),
              std::string::npos)
        << binary.provenance.at("x3p:axes");

    const std::string list_path = directory.file("absolute-list.x3p");
    ASSERT_TRUE(testing::write_zip(
        list_path, {{"main.xml", main_xml(absolute_x, {"A", "D", "1", "0"}, float64_heights(), list + "</DataList>")}}));
    expect_same_field(reference, load_heightfield(list_path));
}

// An X3P whose CX and CY are both `axis` (absolute), with the point records `data`.
std::string write_absolute(const TemporaryDirectory& directory, const std::string& name, const Axis& axis,
                           const std::string& data) {
    const std::string path = directory.file(name);
    EXPECT_TRUE(testing::write_zip(path, {{"main.xml", main_xml(axis, axis, float64_heights(), kDataOnlyLink)},
                                          {"bindata/data.bin", data}}));
    return path;
}

TEST(X3pVariants, AbsoluteAxesOffAGridAreRefusedNamingThePoint) {
    const TemporaryDirectory directory;
    std::string data;
    for (int k = 0; k < kSizeX * kSizeY; ++k) {
        const auto [x, y] = coordinates(0.3)[k];
        append(data, x);
        append(data, y);
        append(data, height_m(k));
    }
    const std::string path = write_absolute(directory, "scattered.x3p", {"A", "D", "1", "0"}, data);
    EXPECT_NE(load_error(path).find("CX axis is not a regular grid: point 5 lies"), std::string::npos)
        << load_error(path);
}

TEST(X3pVariants, IntegerAbsoluteCoordinatesUseTheirIncrementAndOffset) {
    const TemporaryDirectory directory;
    const Heightfield reference = load_heightfield(write_reference(directory));
    std::string data;
    for (int k = 0; k < kSizeX * kSizeY; ++k) {
        append(data, static_cast<std::int16_t>(k % kSizeX * 5));   // 0.5 µm steps: 5 steps a spacing
        append(data, static_cast<std::int16_t>(k / kSizeX * 5));
        append(data, is_valid(k) ? height_m(k) : std::numeric_limits<double>::quiet_NaN());
    }
    const std::string path = write_absolute(directory, "steps.x3p", {"A", "I", "5e-7", "1e-3"}, data);
    expect_same_field(reference, load_heightfield(path));
}

}  // namespace
}  // namespace glintscope
