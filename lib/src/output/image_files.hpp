#pragma once
// Image files as every writer writes them: atomically through OpenImageIO, with the metadata as
// "glintscope:<key>" string attributes (lobe_output.hpp; render outputs share it).
#include <string>
#include <string_view>

#include <OpenImageIO/imageio.h>

#include "glintscope/surface/metadata.hpp"

namespace glintscope {

inline constexpr std::string_view attribute_prefix = "glintscope:";

// Writes through a temporary file renamed into place; throws Error naming the path.
void write_image_file(const std::string& path, const OIIO::ImageSpec& spec, const void* pixels, OIIO::TypeDesc type);

void add_attributes(OIIO::ImageSpec& spec, const Provenance& entries);

// OpenImageIO's messages may span lines; errors are one line.
std::string one_line_message(std::string text);

}  // namespace glintscope
