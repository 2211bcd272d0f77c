#pragma once
// The tables under data/ (CIE colorimetry, metal optical constants, the OpenColorIO config),
// compiled into the library by cmake/embed_data.cmake so that nothing is read from disk at run
// time and the executable works from any directory.
#include <string>
#include <string_view>
#include <vector>

namespace glintscope {

struct EmbeddedFile {
    std::string_view path;  // relative to data/, e.g. "cie/CIE_xyz_1931_2deg.csv"
    std::string_view text;
};

// Every embedded file, sorted by path (defined in the generated source).
const std::vector<EmbeddedFile>& embedded_data_files();

// The text of data/<path>; throws Error if no such file was embedded.
std::string_view embedded_data(std::string_view path);

// A comma-separated numeric table: lines starting with '#' are comments, the first other line
// names the columns, every following line holds one number per column.
struct NumericTable {
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
};

// Parses `text` (named `source` in error messages); throws Error on a malformed line.
NumericTable parse_numeric_table(std::string_view text, const std::string& source);

// The '#' comment lines of a table, without the '#' and leading space, joined by spaces.
std::string table_comment(std::string_view text);

}  // namespace glintscope
