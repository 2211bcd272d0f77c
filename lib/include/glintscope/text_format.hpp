#pragma once
// Numbers and strings as text for metadata, headers and JSON, written one way everywhere.
#include <string>

namespace glintscope {

// The shortest text that reads back as the same double ("0.5", "1e-06", "0.30000000000000004").
std::string shortest_text(double value);

// A JSON string literal with quotes and escapes.
std::string json_string(const std::string& text);

// A JSON number, or null for NaN and infinities (JSON has neither).
std::string json_number(double value);

}  // namespace glintscope
