#include "glintscope/text_format.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace glintscope {

std::string shortest_text(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

std::string json_string(const std::string& text) {
    std::string quoted = "\"";
    for (const char ch : text) {
        switch (ch) {
            case '"': quoted += "\\\""; break;
            case '\\': quoted += "\\\\"; break;
            case '\n': quoted += "\\n"; break;
            case '\r': quoted += "\\r"; break;
            case '\t': quoted += "\\t"; break;
            default:
                if (static_cast<unsigned char>(ch) < 0x20) {
                    char escape[8];
                    std::snprintf(escape, sizeof escape, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(ch)));
                    quoted += escape;
                } else {
                    quoted += ch;
                }
        }
    }
    return quoted + "\"";
}

std::string json_number(double value) { return std::isfinite(value) ? shortest_text(value) : "null"; }

}  // namespace glintscope
