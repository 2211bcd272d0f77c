#include "embedded_data.hpp"

#include <charconv>

#include "glintscope/core/error.hpp"

namespace glintscope {
namespace {

std::string_view trim(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
    return text;
}

std::vector<std::string_view> split_fields(std::string_view line) {
    std::vector<std::string_view> fields;
    for (std::size_t start = 0;;) {
        const std::size_t comma = line.find(',', start);
        fields.push_back(trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start)));
        if (comma == std::string_view::npos) return fields;
        start = comma + 1;
    }
}

double parse_number(std::string_view field, const std::string& source, int line_number) {
    double value = 0.0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (ec != std::errc() || end != field.data() + field.size())
        throw Error(source + " line " + std::to_string(line_number) + ": '" + std::string(field) +
                    "' is not a number");
    return value;
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
        const std::vector<std::string_view> fields = split_fields(line);
        if (table.columns.empty()) {
            for (std::string_view name : fields) table.columns.emplace_back(name);
            return;
        }
        if (fields.size() != table.columns.size())
            throw Error(source + " line " + std::to_string(line_number) + ": expected " +
                        std::to_string(table.columns.size()) + " values, found " + std::to_string(fields.size()));
        std::vector<double> row;
        for (std::string_view field : fields) row.push_back(parse_number(field, source, line_number));
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
