// The X3P writer's main.xml against the openGPS XML schema of ISO 25178-72 (ISO5436_2.xsd,
// openGPS's reference implementation), both of its revisions: the first (2007-04-04) and the
// second (2020-01-20), which adds the values PCL and Software and makes CalibrationDate optional
// but DataType and Increment required on every axis. The schema files are not in Debian, so
// their content models are restated below as facts, read from the files themselves (each
// element's children in schema order with their occurrence bounds, the enumerations and the
// simple types); on 2026-11-27 the written files were also validated against both files with
// libxml2's `xmllint --schema` (docs/heightfields.md says how to repeat it). Elements must
// appear in that order, required ones present, none unknown; values must be of their types. A
// validating reader (openGPS's) checks this, and then the few rules below (schema_problems).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "cli_runner.hpp"
#include "zip_files.hpp"
#include "glintscope/io/heightfield_io.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

enum class Revision { first_2007, second_2020 };

// One particle of an xsd:sequence: an element (or an xsd:choice of elements) and its bounds.
struct Particle {
    std::vector<std::string> names;  // more than one: an xsd:choice
    int min_occurs = 1;
    int max_occurs = 1;
};

constexpr int kUnbounded = std::numeric_limits<int>::max();

// The complex types' content models, by element name.
std::map<std::string, std::vector<Particle>> content_models(Revision revision) {
    const bool second = revision == Revision::second_2020;
    return {
        {"ISO5436_2",
         {{{"Record1"}}, {{"Record2"}, 0, 1}, {{"Record3"}}, {{"Record4"}}, {{"VendorSpecificID"}, 0, second ? kUnbounded : 1}}},
        {"Record1", {{{"Revision"}}, {{"FeatureType"}}, {{"Axes"}}}},
        {"Axes", {{{"CX"}}, {{"CY"}}, {{"CZ"}}, {{"Rotation"}, 0, 1}}},
        {"CX", {{{"AxisType"}}, {{"DataType"}, second ? 1 : 0, 1}, {{"Increment"}, second ? 1 : 0, 1}, {{"Offset"}, 0, 1}}},
        {"Record2",
         {{{"Date"}},
          {{"Creator"}, 0, 1},
          {{"Instrument"}},
          {{"CalibrationDate"}, second ? 0 : 1, 1},
          {{"ProbingSystem"}},
          {{"Comment"}, 0, 1}}},
        {"Instrument", {{{"Manufacturer"}}, {{"Model"}}, {{"Serial"}}, {{"Version"}}}},
        {"ProbingSystem", {{{"Type"}}, {{"Identification"}}}},
        {"Record3", {{{"MatrixDimension", "ListDimension"}}, {{"DataLink", "DataList"}}}},
        {"MatrixDimension", {{{"SizeX"}}, {{"SizeY"}}, {{"SizeZ"}}}},
        // ValidPointsLink and its checksum form an optional inner sequence: both or neither.
        {"DataLink",
         {{{"PointDataLink"}}, {{"MD5ChecksumPointData"}}, {{"ValidPointsLink"}, 0, 1}, {{"MD5ChecksumValidPoints"}, 0, 1}}},
        {"Record4", {{{"ChecksumFile"}}}},
    };
}

// Simple types of the leaves the writer emits.
std::map<std::string, std::regex> leaf_types(Revision revision) {
    const bool second = revision == Revision::second_2020;
    const std::string dbl = R"([+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?)";
    const std::string date_time = R"(-?\d{4,}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?(Z|[+-]\d{2}:\d{2})?)";
    return {
        {"FeatureType", std::regex(second ? "PRF|SUR|PCL" : "PRF|SUR")},
        {"AxisType", std::regex("A|I")},
        {"DataType", std::regex("I|L|F|D")},
        {"Increment", std::regex(dbl)},
        {"Offset", std::regex(dbl)},
        {"Date", std::regex(date_time)},
        {"CalibrationDate", std::regex(date_time)},
        {"Type", std::regex(second ? "Contacting|NonContacting|Software" : "Contacting|NonContacting")},
        {"SizeX", std::regex(R"(\d+)")},
        {"SizeY", std::regex(R"(\d+)")},
        {"SizeZ", std::regex(R"(\d+)")},
        {"MD5ChecksumPointData", std::regex("([0-9a-fA-F]{2})+")},
        {"MD5ChecksumValidPoints", std::regex("([0-9a-fA-F]{2})+")},
    };
}

struct Schema {
    std::map<std::string, std::vector<Particle>> models;
    std::map<std::string, std::regex> leaves;
};

// Checks one element's children against its content model (CY and CZ share CX's type), then
// recurses; each problem is appended as "path: what".
void check_element(const Schema& schema, const pugi::xml_node& node, const std::string& name, const std::string& path,
                   std::vector<std::string>& problems) {
    const std::string model_name = (name == "CY" || name == "CZ") ? "CX" : name;
    const auto model = schema.models.find(model_name);
    if (model == schema.models.end()) {
        const auto type = schema.leaves.find(name);
        const std::string text = node.text().get();
        if (type != schema.leaves.end() && !std::regex_match(text, type->second))
            problems.push_back(path + ": value '" + text + "' is not of its schema type");
        return;
    }
    std::vector<pugi::xml_node> children;
    for (pugi::xml_node child : node.children())
        if (child.type() == pugi::node_element) children.push_back(child);
    std::size_t next = 0;
    for (const Particle& particle : model->second) {
        int count = 0;
        while (next < children.size() && count < particle.max_occurs &&
               std::find(particle.names.begin(), particle.names.end(), children[next].name()) != particle.names.end()) {
            check_element(schema, children[next], children[next].name(), path + "/" + children[next].name(), problems);
            ++next, ++count;
        }
        if (count < particle.min_occurs) problems.push_back(path + ": lacks " + particle.names.front() + " at its place");
    }
    for (; next < children.size(); ++next)
        problems.push_back(path + ": element " + std::string(children[next].name()) + " is out of schema order or unknown");
}

std::vector<std::string> schema_problems(const std::string& xml, Revision revision) {
    const Schema schema{content_models(revision), leaf_types(revision)};
    pugi::xml_document doc;
    if (!doc.load_string(xml.c_str())) return {"main.xml is not well-formed XML"};
    const pugi::xml_node root = doc.document_element();
    std::vector<std::string> problems;
    // The root is the schema's one global element, in its target namespace; the children are
    // unqualified (elementFormDefault="unqualified").
    const std::string root_name = root.name();
    const std::size_t colon = root_name.find(':');
    const std::string prefix = colon == std::string::npos ? "" : root_name.substr(0, colon);
    if (root_name.substr(colon + 1) != "ISO5436_2") problems.push_back("root element is " + root_name);
    const std::string xmlns = prefix.empty() ? "xmlns" : "xmlns:" + prefix;
    if (std::string(root.attribute(xmlns.c_str()).value()) != "http://www.opengps.eu/2008/ISO5436_2")
        problems.push_back("root element is not in the namespace http://www.opengps.eu/2008/ISO5436_2");
    for (pugi::xml_node child : root.children())
        if (child.type() == pugi::node_element && std::string(child.name()).find(':') != std::string::npos)
            problems.push_back(std::string("child ") + child.name() + " is qualified");
    check_element(schema, root, "ISO5436_2", "ISO5436_2", problems);
    const pugi::xml_node link = root.child("Record3").child("DataLink");
    if (link.child("ValidPointsLink").empty() != link.child("MD5ChecksumValidPoints").empty())
        problems.push_back("Record3/DataLink: ValidPointsLink and MD5ChecksumValidPoints must come together");
    // What openGPS's reader checks after the schema (ValidateDocument): CZ absolute, a matrix's
    // incremental CX and CY of non-zero Increment, a profile's matrix one row high.
    const pugi::xml_node axes = root.child("Record1").child("Axes");
    if (std::string(axes.child("CZ").child_value("AxisType")) != "A") problems.push_back("CZ is not absolute");
    for (const char* axis : {"CX", "CY"})
        if (std::string(axes.child(axis).child_value("AxisType")) == "I" && std::atof(axes.child(axis).child_value("Increment")) == 0.0)
            problems.push_back(std::string(axis) + " is incremental with a zero Increment");
    if (std::string(root.child("Record1").child_value("FeatureType")) == "PRF" &&
        std::string(root.child("Record3").child("MatrixDimension").child_value("SizeY")) != "1")
        problems.push_back("a profile's matrix is more than one row high");
    return problems;
}

std::string joined(const std::vector<std::string>& lines) {
    std::string text;
    for (const std::string& line : lines) text += line + "\n";
    return text;
}

// The one problem a file of glintscope's own data has under the first revision: its probing
// system, "Software", a value that revision lacks (and no other value would be true).
const std::string kSoftwareUnder2007 = "ISO5436_2/Record2/ProbingSystem/Type: value 'Software' is not of its schema type";

TEST(X3pSchema, WrittenMainXmlFollowsTheOpenGpsSchema) {
    TemporaryDirectory directory;
    Heightfield field = make_heightfield(3, 5, 0.5);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) field.at(r, c) = static_cast<float>(0.1 * r - 0.02 * c);
    field.provenance["generator"] = "test <&> \"quoted\"";  // escaped in Record2/Comment
    const std::string plain = directory.file("plain.x3p");
    save_heightfield(plain, field);
    field.at(1, 2) = std::numeric_limits<float>::quiet_NaN();  // adds the validity mask's link
    const std::string masked = directory.file("masked.x3p");
    save_heightfield(masked, field);
    for (const std::string& path : {plain, masked}) {
        const std::string xml = testing::read_zip_member(path, "main.xml");
        ASSERT_FALSE(xml.empty()) << path;
        const std::vector<std::string> problems = schema_problems(xml, Revision::second_2020);
        EXPECT_TRUE(problems.empty()) << path << "\n" << joined(problems) << xml;
        EXPECT_EQ(schema_problems(xml, Revision::first_2007), std::vector<std::string>{kSoftwareUnder2007}) << xml;
    }
    EXPECT_NE(testing::read_zip_member(masked, "main.xml").find("<ValidPointsLink>"), std::string::npos);
}

// An instrument's scan as X3P: a 2 × 2 grid of float64 heights and the given Record2.
std::string write_scan(const TemporaryDirectory& directory, const std::string& name, const std::string& record2) {
    std::string data;
    for (const double metres : {1e-7, 2e-7, -1e-7, 3e-7}) data.append(reinterpret_cast<const char*>(&metres), sizeof metres);
    const std::string axis = "<AxisType>I</AxisType><DataType>D</DataType><Increment>2.5e-06</Increment><Offset>0</Offset>";
    const std::string xml =
        "<p:ISO5436_2 xmlns:p=\"http://www.opengps.eu/2008/ISO5436_2\"><Record1><Revision>ISO5436 - 2000</Revision>"
        "<FeatureType>SUR</FeatureType><Axes><CX>" + axis + "</CX><CY>" + axis +
        "</CY><CZ><AxisType>A</AxisType><DataType>D</DataType><Increment>1</Increment><Offset>0</Offset></CZ></Axes>"
        "</Record1>" + record2 +
        "<Record3><MatrixDimension><SizeX>2</SizeX><SizeY>2</SizeY><SizeZ>1</SizeZ></MatrixDimension>"
        "<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink></Record3>"
        "<Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4></p:ISO5436_2>";
    const std::string path = directory.file(name);
    EXPECT_TRUE(testing::write_zip(path, {{"main.xml", xml}, {"bindata/data.bin", data}}));
    return path;
}

// Record2 of main.xml with its Date (the time of writing) removed.
std::string record2_without_date(const std::string& xml) {
    pugi::xml_document doc;
    doc.load_string(xml.c_str());
    pugi::xml_node record2 = doc.document_element().child("Record2");
    record2.remove_child("Date");
    record2.remove_child("Comment");
    std::ostringstream text;
    record2.print(text, "", pugi::format_raw);
    return text.str();
}

TEST(X3pSchema, ConvertedScanNamesItsInstrumentAndFollowsBothRevisions) {
    TemporaryDirectory directory;
    const std::string measured =
        "<Creator>A. Metrologist</Creator><Instrument><Manufacturer>Alicona</Manufacturer>"
        "<Model>InfiniteFocus G5</Model><Serial>0451</Serial><Version>5.3.1</Version></Instrument>"
        "<CalibrationDate>2025-06-01T10:00:00+02:00</CalibrationDate><ProbingSystem><Type>NonContacting</Type>"
        "<Identification>10x objective</Identification></ProbingSystem>";
    const std::string scan = write_scan(directory, "scan.x3p", "<Record2><Date>2025-06-02T09:15:00</Date>" + measured +
                                                                   "<Comment>levelled</Comment></Record2>");
    const Heightfield field = load_heightfield(scan);
    EXPECT_EQ(field.provenance.at("x3p:instrument"), "Alicona InfiniteFocus G5 5.3.1");
    EXPECT_EQ(field.provenance.at("x3p:probing_system.type"), "NonContacting");
    const std::string converted = directory.file("converted.x3p");
    save_heightfield(converted, field);
    const std::string xml = testing::read_zip_member(converted, "main.xml");
    for (const Revision revision : {Revision::first_2007, Revision::second_2020})
        EXPECT_TRUE(schema_problems(xml, revision).empty()) << joined(schema_problems(xml, revision)) << xml;
    // The measurement's description is the scan's, element for element; our own file, read and
    // written again, keeps it (from the provenance in its Comment).
    EXPECT_EQ(record2_without_date(xml), "<Record2>" + measured + "</Record2>");
    const std::string again = directory.file("again.x3p");
    save_heightfield(again, load_heightfield(converted));
    EXPECT_EQ(record2_without_date(testing::read_zip_member(again, "main.xml")), record2_without_date(xml));
}

TEST(X3pSchema, ADateThatIsNotAnXsdDateTimeIsLeftOutNotCopied) {
    TemporaryDirectory directory;
    const std::string scan = write_scan(directory, "scan.x3p",
                                        "<Record2><Date>30.01.2018</Date><Instrument><Manufacturer>Keyence</Manufacturer>"
                                        "<Model>VK-X1000</Model><Serial></Serial><Version>N/A</Version></Instrument>"
                                        "<CalibrationDate>30.01.2018</CalibrationDate><ProbingSystem>"
                                        "<Type>NonContacting</Type><Identification/></ProbingSystem></Record2>");
    const std::string converted = directory.file("converted.x3p");
    save_heightfield(converted, load_heightfield(scan));
    const std::string xml = testing::read_zip_member(converted, "main.xml");
    EXPECT_TRUE(schema_problems(xml, Revision::second_2020).empty()) << joined(schema_problems(xml, Revision::second_2020));
    EXPECT_EQ(record2_without_date(xml),
              "<Record2><Instrument><Manufacturer>Keyence</Manufacturer><Model>VK-X1000</Model><Serial>N/A</Serial>"
              "<Version>N/A</Version></Instrument><ProbingSystem><Type>NonContacting</Type>"
              "<Identification>N/A</Identification></ProbingSystem></Record2>");
}

TEST(X3pSchema, TheCheckerRejectsOutOfOrderMissingAndMistypedElements) {
    // The checker itself: a minimal valid document, then ways to break it.
    const std::string axes =
        "<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-6</Increment></CX>"
        "<CY><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-6</Increment></CY>"
        "<CZ><AxisType>A</AxisType><DataType>D</DataType><Increment>1</Increment></CZ>";
    const std::string valid =
        "<p:ISO5436_2 xmlns:p=\"http://www.opengps.eu/2008/ISO5436_2\"><Record1><Revision>ISO5436 - 2000</Revision>"
        "<FeatureType>SUR</FeatureType><Axes>" + axes + "</Axes></Record1>"
        "<Record2><Date>2026-11-27T10:00:00Z</Date><Instrument><Manufacturer>N/A</Manufacturer><Model>N/A</Model>"
        "<Serial>N/A</Serial><Version>N/A</Version></Instrument><CalibrationDate>2026-01-01T00:00:00Z</CalibrationDate>"
        "<ProbingSystem><Type>Contacting</Type><Identification>N/A</Identification></ProbingSystem></Record2>"
        "<Record3><MatrixDimension><SizeX>1</SizeX><SizeY>1</SizeY><SizeZ>1</SizeZ></MatrixDimension>"
        "<DataLink><PointDataLink>bindata/data.bin</PointDataLink>"
        "<MD5ChecksumPointData>00112233445566778899aabbccddeeff</MD5ChecksumPointData></DataLink></Record3>"
        "<Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4></p:ISO5436_2>";
    for (const Revision revision : {Revision::first_2007, Revision::second_2020})
        EXPECT_TRUE(schema_problems(valid, revision).empty()) << joined(schema_problems(valid, revision));
    const auto problems = [&](const std::string& from, const std::string& to, Revision revision) {
        std::string xml = valid;
        xml.replace(xml.find(from), from.size(), to);
        return schema_problems(xml, revision).size();
    };
    for (const Revision revision : {Revision::first_2007, Revision::second_2020}) {
        EXPECT_GT(problems("<Revision>ISO5436 - 2000</Revision><FeatureType>SUR</FeatureType>",
                           "<FeatureType>SUR</FeatureType><Revision>ISO5436 - 2000</Revision>", revision),
                  0u);
        EXPECT_GT(problems("<Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4>", "", revision), 0u);
        EXPECT_GT(problems("<FeatureType>SUR</FeatureType>", "<FeatureType>AREA</FeatureType>", revision), 0u);
        EXPECT_GT(problems("<CZ><AxisType>A</AxisType>", "<CZ><AxisType>I</AxisType>", revision), 0u);
        EXPECT_GT(problems("<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-6</Increment>",
                           "<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>0</Increment>", revision),
                  0u);
    }
    // Where the revisions differ.
    const std::string z_increment = "<DataType>D</DataType><Increment>1</Increment></CZ>";
    EXPECT_EQ(problems(z_increment, "<DataType>D</DataType></CZ>", Revision::first_2007), 0u);
    EXPECT_EQ(problems(z_increment, "<DataType>D</DataType></CZ>", Revision::second_2020), 1u);
    const std::string calibration = "<CalibrationDate>2026-01-01T00:00:00Z</CalibrationDate>";
    EXPECT_EQ(problems(calibration, "", Revision::first_2007), 1u);
    EXPECT_EQ(problems(calibration, "", Revision::second_2020), 0u);
    EXPECT_EQ(problems("<Type>Contacting</Type>", "<Type>Software</Type>", Revision::first_2007), 1u);
    EXPECT_EQ(problems("<Type>Contacting</Type>", "<Type>Software</Type>", Revision::second_2020), 0u);
}

}  // namespace
}  // namespace glintscope
