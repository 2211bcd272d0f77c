#include "embedded_data.hpp"

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

// A table field as a number; the error names the table and the line.
double parse_field(std::string_view field, const std::string& source, int line_number) {
    try {
        return parse_number(field);
    } catch (const Error& e) {
        throw Error(source + " line " + std::to_string(line_number) + ": " + e.what());
    }
}

// Calls visit(line, line_number) for each line of `text`.
template <typename Visit>
void for_each_line(std::string_view text, Visit visit) {
    int line_number = 0;
    while (!text.empty()) {
        const std::size_t newline = text.find('\n');
        visit(trim(text.substr(0, newline)), ++line_number);
        if (newline == std::string_view::npos) break;
        text.remove_prefix(newline + 1);
    }
}

}  // namespace

std::string_view embedded_data(std::string_view path) {
    for (const EmbeddedFile& file : embedded_data_files())
        if (file.path == path) return file.text;
    throw Error("data file '" + std::string(path) + "' is not built into this executable");
}

NumericTable parse_numeric_table(std::string_view text, const std::string& source) {
    NumericTable table;
    for_each_line(text, [&](std::string_view line, int line_number) {
        if (line.empty() || line.front() == '#') return;
        const std::vector<std::string> fields = split(line, ',');
        if (table.columns.empty()) {
            table.columns = fields;
            return;
        }
        if (fields.size() != table.columns.size())
            throw Error(source + " line " + std::to_string(line_number) + ": expected " +
                        std::to_string(table.columns.size()) + " values, found " + std::to_string(fields.size()));
        std::vector<double> row;
        for (const std::string& field : fields) row.push_back(parse_field(field, source, line_number));
        table.rows.push_back(std::move(row));
    });
    if (table.rows.empty()) throw Error(source + ": the table has no rows");
    return table;
}

std::string table_comment(std::string_view text) {
    std::string comment;
    for_each_line(text, [&](std::string_view line, int) {
        if (line.empty() || line.front() != '#') return;
        line.remove_prefix(1);
        line = trim(line);
        if (line.empty()) return;
        if (!comment.empty()) comment += ' ';
        comment += line;
    });
    return comment;
}

}  // namespace glintscope
