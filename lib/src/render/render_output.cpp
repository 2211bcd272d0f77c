#include "glintscope/render/render_output.hpp"

#include <OpenImageIO/imageio.h>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "output/image_files.hpp"

namespace glintscope {
namespace {

void check_image(const RenderImage& image) {
    if (image.width < 1 || image.height < 1 || image.wavelengths_um.empty() ||
        image.values.size() != image.pixels() * image.wavelengths_um.size())
        throw Error("render image is empty or its values do not match its size and wavelengths");
}

std::vector<float> render_xyz(const RenderImage& image, const ColourSettings& colour) {
    return layers_to_xyz(image.values, image.pixels(), image.wavelengths_um, colour.illuminant);
}

Provenance output_facts(const RenderImage& image, const ColourSettings& colour, const std::string& channels) {
    Provenance facts;
    facts["output.units"] = "W m^-2 sr^-1";
    facts["output.wavelengths_um"] = join_numbers(image.wavelengths_um);
    facts["output.channels"] = channels;
    facts["output.image"] = "pinhole camera view, row 0 at the top";
    if (image.wavelengths_um.size() > 1) {
        facts["output.illuminant"] = to_string(colour.illuminant);
        facts["output.colour_config"] = colour_config_name(colour);
    }
    return facts;
}

}  // namespace

void write_render_exr(const RenderImage& image, const std::string& path, const ColourSettings& colour) {
    check_image(image);
    const bool spectral = image.wavelengths_um.size() > 1;
    std::vector<float> pixels;
    Provenance facts;
    OIIO::ImageSpec spec(image.width, image.height, spectral ? 3 : 1, OIIO::TypeDesc::FLOAT);
    if (spectral) {
        pixels = render_xyz(image, colour);
        convert_from_xyz(pixels, colour, colour.output_space);
        spec.channelnames = {"R", "G", "B"};
        facts = output_facts(image, colour, "R, G, B linear " + colour.output_space);
        facts["output.colour_space"] = colour.output_space;
        const std::vector<float> primaries = scene_linear_chromaticities(colour, colour.output_space);
        if (!primaries.empty()) spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), primaries.data());
    } else {
        pixels = image.values;
        spec.channelnames = {"Y"};
        facts = output_facts(image, colour, "Y = radiance at " + shortest_text(image.wavelengths_um[0]) + " um");
    }
    spec.attribute("compression", "zip");
    add_attributes(spec, image.metadata);
    add_attributes(spec, facts);
    write_image_file(path, spec, pixels.data(), OIIO::TypeDesc::FLOAT);
}

DisplayExposure write_render_png(const RenderImage& image, const std::string& path, const ColourSettings& colour) {
    check_image(image);
    std::vector<float> xyz = render_xyz(image, colour);
    const DisplayExposure exposure = xyz_exposure(xyz, colour);
    const std::vector<std::uint8_t> pixels = xyz_to_display(std::move(xyz), exposure, colour);
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    add_attributes(spec, image.metadata);
    Provenance facts = output_facts(image, colour, "display-referred " + colour.display_space);
    facts["output.exposure_ev"] = shortest_text(exposure.ev);
    facts["output.exposure_rule"] = exposure.rule;
    facts["output.white_level"] = shortest_text(exposure.white_level) + " W m^-2 sr^-1 (luminance Y shown as 1)";
    add_attributes(spec, facts);
    write_image_file(path, spec, pixels.data(), OIIO::TypeDesc::UINT8);
    return exposure;
}

RenderExr load_render_exr(const std::string& path) {
    auto input = OIIO::ImageInput::open(path);
    if (!input) throw Error("cannot read render '" + path + "': " + one_line_message(OIIO::geterror()));
    const OIIO::ImageSpec& spec = input->spec();
    RenderExr exr;
    exr.width = spec.width;
    exr.height = spec.height;
    exr.channels = spec.channelnames;
    std::vector<float> interleaved(std::size_t(spec.width) * spec.height * spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, interleaved.data()))
        throw Error("cannot read render '" + path + "': " + one_line_message(input->geterror()));
    const std::size_t pixels = std::size_t(spec.width) * spec.height;
    exr.values.resize(interleaved.size());
    for (std::size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < spec.nchannels; ++c) exr.values[c * pixels + i] = interleaved[i * spec.nchannels + c];
    return exr;
}

}  // namespace glintscope
