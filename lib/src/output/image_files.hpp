#pragma once
// Image files as every writer writes them: atomically through OpenImageIO, with the metadata as
// "glintscope:<key>" string attributes (lobe_output.hpp; render outputs share it).
#include <string>
#include <string_view>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "glintscope/core/error.hpp"
#include "glintscope/surface/metadata.hpp"

namespace glintscope {

inline constexpr std::string_view attribute_prefix = "glintscope:";

// Writes through a temporary file renamed into place; throws Error naming the path.
void write_image_file(const std::string& path, const OIIO::ImageSpec& spec, const void* pixels, OIIO::TypeDesc type);

void add_attributes(OIIO::ImageSpec& spec, const Provenance& entries);

// OpenImageIO's messages may span lines; errors are one line.
std::string one_line_message(std::string text);

// Reads an image's first `channels` channels (0: all) as T, interleaved, into `pixels` and returns
// its spec; throws Error "cannot read WHAT 'PATH': problem".
template <class T>
OIIO::ImageSpec read_image_file(const std::string& path, const std::string& what, int channels, std::vector<T>& pixels) {
    auto input = OIIO::ImageInput::open(path);
    if (!input) throw Error("cannot read " + what + " '" + path + "': " + one_line_message(OIIO::geterror()));
    const OIIO::ImageSpec spec = input->spec();
    const int count = channels ? channels : spec.nchannels;
    if (spec.nchannels < count) throw Error("cannot read " + what + " '" + path + "': it has fewer than " + std::to_string(count) + " channels");
    pixels.resize(std::size_t(spec.width) * spec.height * count);
    if (!input->read_image(0, 0, 0, count, OIIO::BaseTypeFromC<T>::value, pixels.data()))
        throw Error("cannot read " + what + " '" + path + "': " + one_line_message(input->geterror()));
    return spec;
}

}  // namespace glintscope
