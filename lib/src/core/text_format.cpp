#include "glintscope/core/text_format.hpp"

#include <cctype>
#include <charconv>
#include <cmath>

#include "glintscope/core/error.hpp"

namespace glintscope {

std::string shortest_text(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

std::string join_numbers(const std::vector<double>& values, const std::string& separator) {
    std::string text;
    for (std::size_t i = 0; i < values.size(); ++i) text += (i ? separator : "") + shortest_text(values[i]);
    return text;
}

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
    std::string text;
    for (std::size_t i = 0; i < parts.size(); ++i) text += (i ? separator : "") + parts[i];
    return text;
}

std::string_view trim(std::string_view text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
    return text;
}

std::vector<std::string> split(std::string_view text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find(separator, start);
        parts.emplace_back(trim(text.substr(start, end == std::string_view::npos ? end : end - start)));
        if (end == std::string_view::npos) return parts;
        start = end + 1;
    }
}

double parse_number(std::string_view text) {
    const std::string_view trimmed = trim(text);
    const char* first = trimmed.data();
    const char* last = first + trimmed.size();
    if (first != last && *first == '+') ++first;
    double value = 0.0;
    const auto [end, ec] = std::from_chars(first, last, value);
    if (ec != std::errc() || end != last || first == last) throw Error("'" + std::string(text) + "' is not a number");
    if (!std::isfinite(value)) throw Error("'" + std::string(text) + "' is not finite");
    return value;
}

long long parse_integer(std::string_view text, long long min, long long max) {
    const std::string_view trimmed = trim(text);
    long long value = 0;
    const auto [end, ec] = std::from_chars(trimmed.data(), trimmed.data() + trimmed.size(), value);
    if (ec != std::errc() || end != trimmed.data() + trimmed.size() || trimmed.empty())
        throw Error("'" + std::string(text) + "' is not a whole number");
    if (value < min || value > max)
        throw Error("'" + std::string(text) + "' is not between " + std::to_string(min) + " and " + std::to_string(max));
    return value;
}

std::uint64_t parse_unsigned(std::string_view text) {
    const std::string_view trimmed = trim(text);
    std::uint64_t value = 0;
    const auto [end, ec] = std::from_chars(trimmed.data(), trimmed.data() + trimmed.size(), value);
    if (ec == std::errc::result_out_of_range) throw Error("'" + std::string(text) + "' is out of range");
    if (ec != std::errc() || end != trimmed.data() + trimmed.size() || trimmed.empty())
        throw Error("'" + std::string(text) + "' is not a whole number");
    return value;
}

std::vector<double> parse_number_list(std::string_view text) {
    std::vector<double> values;
    for (const std::string& part : split(text, ',')) values.push_back(parse_number(part));
    return values;
}

}  // namespace glintscope
