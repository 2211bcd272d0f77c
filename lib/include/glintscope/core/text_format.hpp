#pragma once
// Numbers and strings as text for metadata, headers and messages, written and read one way
// everywhere (JSON is written with nlohmann::json).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace glintscope {

// The shortest text that reads back as the same double ("0.5", "1e-06", "0.30000000000000004").
std::string shortest_text(double value);

// Values in shortest_text joined by `separator`: {0.5, 1} → "0.5,1".
std::string join_numbers(const std::vector<double>& values, const std::string& separator = ",");

// Parts joined by `separator`.
std::string join(const std::vector<std::string>& parts, const std::string& separator = ", ");

// Without leading and trailing white space.
std::string_view trim(std::string_view text);

// `text` cut at every `separator`, each part trimmed.
std::vector<std::string> split(std::string_view text, char separator);

// A finite number (leading '+' allowed, white space around it ignored); throws Error
// "'TEXT' is not a number" otherwise.
double parse_number(std::string_view text);

// A whole number in [min, max]; throws Error naming the text and the range otherwise.
long long parse_integer(std::string_view text, long long min, long long max);
std::uint64_t parse_unsigned(std::string_view text);

// Comma-separated finite numbers ("0.5,0.6"); throws Error otherwise.
std::vector<double> parse_number_list(std::string_view text);

}  // namespace glintscope
