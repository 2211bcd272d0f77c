#include "glintscope/render/render_output.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "output/drawing.hpp"
#include "output/image_files.hpp"

namespace glintscope {
namespace {

constexpr int kSheetGap = 2;                  // pixels between a contact sheet's frames
constexpr std::uint8_t kSheetGapGrey = 96;    // display value of the gaps
constexpr int kSheetLabel = 20;               // pixels of the label strip above each frame

// A sweep frame's label: its number and where its (first) light is, in mm, read from the
// metadata the frame's files record ("x,y,z:I;…" in um), so that the sheet says what its files say.
std::string sweep_frame_label(const RenderImage& frame, std::size_t k, std::size_t count) {
    std::string label = std::to_string(k + 1) + "/" + std::to_string(count);
    const auto lights = frame.metadata.find("render.lights_um_w_per_sr");
    if (lights == frame.metadata.end()) return label;
    double x = 0.0, y = 0.0, z = 0.0;
    if (std::sscanf(lights->second.c_str(), "%lf,%lf,%lf:", &x, &y, &z) != 3) return label;
    return label + "  light at (" + drawing::number(x / 1000.0, 4) + ", " + drawing::number(y / 1000.0, 4) + ", " +
           drawing::number(z / 1000.0, 4) + ") mm";
}

// The strip above a sheet's frame: its label in white on the gaps' grey, cut at the frame's width.
void draw_sweep_label(std::vector<std::uint8_t>& sheet, int sheet_width, int sheet_height, int left, int top, int width,
                      const std::string& label) {
    OIIO::ImageBuf strip(OIIO::ImageSpec(width, kSheetLabel, 3, OIIO::TypeDesc::FLOAT));
    const float grey = kSheetGapGrey / 255.0f;
    OIIO::ImageBufAlgo::fill(strip, {grey, grey, grey});
    drawing::text(strip, 4, (kSheetLabel - drawing::kFont) / 2, label, drawing::kWhite);
    OIIO::ImageBuf canvas(OIIO::ImageSpec(sheet_width, sheet_height, 3, OIIO::TypeDesc::UINT8), sheet.data());
    drawing::paste(canvas, strip, left, top);
}

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

DisplayExposure write_sweep_pngs(const std::vector<RenderImage>& frames, const std::vector<std::string>& frame_paths,
                                 const std::string& sheet_path, const ColourSettings& colour) {
    if (frames.empty() || frame_paths.size() != frames.size())
        throw Error("a light sweep needs one PNG path per frame");
    std::vector<std::vector<float>> xyz;
    std::vector<float> all;
    for (const RenderImage& frame : frames) {
        check_image(frame);
        if (frame.width != frames[0].width || frame.height != frames[0].height)
            throw Error("the frames of a light sweep must share their size");
        xyz.push_back(render_xyz(frame, colour));
        all.insert(all.end(), xyz.back().begin(), xyz.back().end());
    }
    const DisplayExposure exposure = xyz_exposure(all, colour);
    ColourSettings fixed = colour;
    fixed.exposure_ev = exposure.ev;
    const int width = frames[0].width, height = frames[0].height;
    const int columns = static_cast<int>(std::ceil(std::sqrt(double(frames.size()))));
    const int rows = static_cast<int>((frames.size() + columns - 1) / columns);
    // Frames of glints are mostly black: grey gaps keep their edges apart; a tile without a frame
    // is black; above each frame a strip names it and its light.
    const int tile_height = kSheetLabel + height;
    const int sheet_width = columns * width + (columns - 1) * kSheetGap;
    const int sheet_height = rows * tile_height + (rows - 1) * kSheetGap;
    std::vector<std::uint8_t> sheet(std::size_t(sheet_width) * sheet_height * 3, kSheetGapGrey);
    for (std::size_t k = 0; k < std::size_t(columns) * rows; ++k) {
        std::vector<std::uint8_t> pixels(std::size_t(width) * height * 3, 0);
        const int left = int(k % columns) * (width + kSheetGap);
        const int top = int(k / columns) * (tile_height + kSheetGap);
        if (k < frames.size()) {
            write_render_png(frames[k], frame_paths[k], fixed);
            pixels = xyz_to_display(std::move(xyz[k]), exposure, colour);
            draw_sweep_label(sheet, sheet_width, sheet_height, left, top, width,
                             sweep_frame_label(frames[k], k, frames.size()));
        }
        for (int row = 0; row < height; ++row)
            std::copy_n(pixels.begin() + std::size_t(row) * width * 3, std::size_t(width) * 3,
                        sheet.begin() + ((std::size_t(top) + kSheetLabel + row) * sheet_width + left) * 3);
    }
    OIIO::ImageSpec spec(sheet_width, sheet_height, 3, OIIO::TypeDesc::UINT8);
    add_attributes(spec, frames[0].metadata);
    Provenance facts = output_facts(frames[0], colour, "display-referred " + colour.display_space);
    facts["output.image"] = "light sweep contact sheet: " + std::to_string(frames.size()) + " frames, " +
                            std::to_string(columns) + " per row, row-major, each under a " +
                            std::to_string(kSheetLabel) + "-pixel strip naming it and its first light's position, " +
                            std::to_string(kSheetGap) + "-pixel grey gaps";
    facts["output.exposure_ev"] = shortest_text(exposure.ev);
    facts["output.exposure_rule"] = exposure.rule + ", one for every frame";
    add_attributes(spec, facts);
    write_image_file(sheet_path, spec, sheet.data(), OIIO::TypeDesc::UINT8);
    return exposure;
}

std::vector<std::string> render_caption(const Provenance& metadata) {
    const auto value = [&](const std::string& key) {
        const auto it = metadata.find(key);
        return it == metadata.end() ? std::string() : it->second;
    };
    std::vector<std::string> first = {value("method").empty() ? "?" : value("method")};
    if (!value("method").empty() && !renders_pixel_footprint(value("method")) && !value("query.model").empty())
        first.push_back(value("query.model"));
    if (!value("query.material").empty() && value("query.material") != "none") first.push_back(value("query.material"));
    std::vector<double> nm;
    for (const std::string& um : split(value("output.wavelengths_um"), ',')) nm.push_back(parse_number(um) * 1e3);
    const std::string wavelengths = nm.empty()       ? "lambda ?"
                                    : nm.size() == 1 ? "lambda " + shortest_text(nm[0]) + " nm"
                                                     : "lambda " + shortest_text(std::round(nm.front())) + "-" +
                                                           shortest_text(std::round(nm.back())) + " nm, " +
                                                           std::to_string(nm.size()) + " bins";
    const std::string rule = value("output.exposure_rule");
    char ev[32] = "?";
    if (!value("output.exposure_ev").empty()) std::snprintf(ev, sizeof ev, "%.2f", parse_number(value("output.exposure_ev")));
    const std::string exposure = "exposure " + std::string(ev) + " EV" +
                                 (rule.starts_with("auto") ? " (auto)" : rule.empty() ? "" : " (given)");
    return {join(first, ", "), wavelengths, value("render.size") + ", " + value("render.spp") + " spp, " + exposure};
}

RenderExr load_render_exr(const std::string& path) {
    std::vector<float> interleaved;
    const OIIO::ImageSpec spec = read_image_file(path, "render", 0, interleaved);
    RenderExr exr;
    exr.width = spec.width;
    exr.height = spec.height;
    exr.channels = spec.channelnames;
    const std::size_t pixels = std::size_t(spec.width) * spec.height;
    exr.values.resize(interleaved.size());
    for (std::size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < spec.nchannels; ++c) exr.values[c * pixels + i] = interleaved[i * spec.nchannels + c];
    return exr;
}

}  // namespace glintscope
