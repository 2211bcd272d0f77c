#include "output/image_files.hpp"

#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope {

std::string one_line_message(std::string text) {
    for (char& ch : text)
        if (ch == '\n' || ch == '\r') ch = ' ';
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text.empty() ? "unknown error" : text;
}

void write_image_file(const std::string& path, const OIIO::ImageSpec& spec, const void* pixels, OIIO::TypeDesc type) {
    write_atomically(path, [&](const std::string& temporary) {
        auto output = OIIO::ImageOutput::create(temporary);
        if (!output) throw Error("cannot write '" + path + "': " + one_line_message(OIIO::geterror()));
        if (!output->open(temporary, spec) || !output->write_image(type, pixels) || !output->close())
            throw Error("cannot write '" + path + "': " + one_line_message(output->geterror()));
    });
}

void add_attributes(OIIO::ImageSpec& spec, const Provenance& entries) {
    for (const auto& [key, value] : entries) spec.attribute(std::string(attribute_prefix) + key, value);
}

}  // namespace glintscope
