// The X3P writer's main.xml against the openGPS XML schema of ISO 5436-2 (ISO5436_2.xsd, the
// 2007 revision; the schema is not installed here, so its content model is restated below as
// facts: each element's children in schema order with their occurrence bounds, the
// enumerations and the simple types). Elements must appear in that order, required ones present,
// none unknown; values must be of their types. A validating reader (openGPS's) checks exactly
// this, so a file that passes here is schema-valid in structure and simple types.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "cli_runner.hpp"
#include "zip_files.hpp"
#include "glintscope/io/heightfield_io.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

// One particle of an xsd:sequence: an element (or an xsd:choice of elements) and its bounds.
struct Particle {
    std::vector<std::string> names;  // more than one: an xsd:choice
    int min_occurs = 1;
    int max_occurs = 1;
};

// The complex types' content models, by element name (ISO5436_2.xsd, openGPS, 2007).
const std::map<std::string, std::vector<Particle>>& content_models() {
    static const std::map<std::string, std::vector<Particle>> models = {
        {"ISO5436_2", {{{"Record1"}}, {{"Record2"}, 0, 1}, {{"Record3"}}, {{"Record4"}}, {{"VendorSpecificID"}, 0, 1}}},
        {"Record1", {{{"Revision"}}, {{"FeatureType"}}, {{"Axes"}}}},
        {"Axes", {{{"CX"}}, {{"CY"}}, {{"CZ"}}, {{"Rotation"}, 0, 1}}},
        {"CX", {{{"AxisType"}}, {{"DataType"}, 0, 1}, {{"Increment"}, 0, 1}, {{"Offset"}, 0, 1}}},
        {"Record2",
         {{{"Date"}}, {{"Creator"}, 0, 1}, {{"Instrument"}}, {{"CalibrationDate"}}, {{"ProbingSystem"}}, {{"Comment"}, 0, 1}}},
        {"Instrument", {{{"Manufacturer"}}, {{"Model"}}, {{"Serial"}}, {{"Version"}}}},
        {"ProbingSystem", {{{"Type"}}, {{"Identification"}}}},
        {"Record3", {{{"MatrixDimension", "ListDimension"}}, {{"DataLink", "DataList"}}}},
        {"MatrixDimension", {{{"SizeX"}}, {{"SizeY"}}, {{"SizeZ"}}}},
        // ValidPointsLink and its checksum form an optional inner sequence: both or neither.
        {"DataLink",
         {{{"PointDataLink"}}, {{"MD5ChecksumPointData"}}, {{"ValidPointsLink"}, 0, 1}, {{"MD5ChecksumValidPoints"}, 0, 1}}},
        {"Record4", {{{"ChecksumFile"}}}},
    };
    return models;
}

// Simple types of the leaves the writer emits.
const std::map<std::string, std::regex>& leaf_types() {
    const std::string dbl = R"([+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?)";
    const std::string date_time = R"(-?\d{4,}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?(Z|[+-]\d{2}:\d{2})?)";
    static const std::map<std::string, std::regex> types = {
        {"FeatureType", std::regex("PRF|SUR|PCL")},
        {"AxisType", std::regex("A|I")},
        {"DataType", std::regex("I|L|F|D")},
        {"Increment", std::regex(dbl)},
        {"Offset", std::regex(dbl)},
        {"Date", std::regex(date_time)},
        {"CalibrationDate", std::regex(date_time)},
        {"Type", std::regex("Contacting|NonContacting|Software")},
        {"SizeX", std::regex(R"(\d+)")},
        {"SizeY", std::regex(R"(\d+)")},
        {"SizeZ", std::regex(R"(\d+)")},
        {"MD5ChecksumPointData", std::regex("([0-9a-fA-F]{2})+")},
        {"MD5ChecksumValidPoints", std::regex("([0-9a-fA-F]{2})+")},
    };
    return types;
}

// Checks one element's children against its content model (CY and CZ share CX's type), then
// recurses; each problem is appended as "path: what".
void check_element(const pugi::xml_node& node, const std::string& name, const std::string& path,
                   std::vector<std::string>& problems) {
    const std::string model_name = (name == "CY" || name == "CZ") ? "CX" : name;
    const auto model = content_models().find(model_name);
    if (model == content_models().end()) {
        const auto type = leaf_types().find(name);
        const std::string text = node.text().get();
        if (type != leaf_types().end() && !std::regex_match(text, type->second))
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
            check_element(children[next], children[next].name(), path + "/" + children[next].name(), problems);
            ++next, ++count;
        }
        if (count < particle.min_occurs) problems.push_back(path + ": lacks " + particle.names.front() + " at its place");
    }
    for (; next < children.size(); ++next)
        problems.push_back(path + ": element " + std::string(children[next].name()) + " is out of schema order or unknown");
}

std::vector<std::string> schema_problems(const std::string& xml) {
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
    check_element(root, "ISO5436_2", "ISO5436_2", problems);
    const pugi::xml_node link = root.child("Record3").child("DataLink");
    if (link.child("ValidPointsLink").empty() != link.child("MD5ChecksumValidPoints").empty())
        problems.push_back("Record3/DataLink: ValidPointsLink and MD5ChecksumValidPoints must come together");
    return problems;
}

std::string joined(const std::vector<std::string>& lines) {
    std::string text;
    for (const std::string& line : lines) text += line + "\n";
    return text;
}

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
        const std::vector<std::string> problems = schema_problems(xml);
        EXPECT_TRUE(problems.empty()) << path << "\n" << joined(problems) << xml;
    }
    EXPECT_NE(testing::read_zip_member(masked, "main.xml").find("<ValidPointsLink>"), std::string::npos);
}

TEST(X3pSchema, TheCheckerRejectsOutOfOrderMissingAndMistypedElements) {
    // The checker itself: a minimal valid document, then three ways to break it.
    const std::string valid =
        "<p:ISO5436_2 xmlns:p=\"http://www.opengps.eu/2008/ISO5436_2\"><Record1><Revision>ISO5436 - 2000</Revision>"
        "<FeatureType>SUR</FeatureType><Axes><CX><AxisType>I</AxisType><Increment>1e-6</Increment></CX>"
        "<CY><AxisType>I</AxisType><Increment>1e-6</Increment></CY><CZ><AxisType>A</AxisType><DataType>D</DataType></CZ>"
        "</Axes></Record1><Record3><MatrixDimension><SizeX>1</SizeX><SizeY>1</SizeY><SizeZ>1</SizeZ></MatrixDimension>"
        "<DataLink><PointDataLink>bindata/data.bin</PointDataLink>"
        "<MD5ChecksumPointData>00112233445566778899aabbccddeeff</MD5ChecksumPointData></DataLink></Record3>"
        "<Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4></p:ISO5436_2>";
    EXPECT_TRUE(schema_problems(valid).empty()) << joined(schema_problems(valid));
    const auto broken = [&](const std::string& from, const std::string& to) {
        std::string xml = valid;
        xml.replace(xml.find(from), from.size(), to);
        return schema_problems(xml).size();
    };
    EXPECT_GT(broken("<Revision>ISO5436 - 2000</Revision><FeatureType>SUR</FeatureType>",
                     "<FeatureType>SUR</FeatureType><Revision>ISO5436 - 2000</Revision>"),
              0u);
    EXPECT_GT(broken("<Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4>", ""), 0u);
    EXPECT_GT(broken("<FeatureType>SUR</FeatureType>", "<FeatureType>AREA</FeatureType>"), 0u);
}

}  // namespace
}  // namespace glintscope
