#pragma once
// Writing renders, atomically, through the colour pipeline of spectral lobes (colour.hpp):
// EXR (scene-linear float, zip): one wavelength is channel "Y", the radiance in W m⁻² sr⁻¹; a
// spectrum is R, G, B in the output colour space (CIE → XYZ → OpenColorIO), weighted by the
// lights' spectrum as the illuminant. PNG: display-referred, exposed by the settings (auto: the
// 99.5th percentile of luminance maps to 1), the exposure recorded as "glintscope:output.exposure_ev".
// Both carry the render's metadata as "glintscope:<key>" attributes.
#include <string>
#include <vector>

#include "glintscope/output/colour.hpp"
#include "glintscope/render/render.hpp"

namespace glintscope {

void write_render_exr(const RenderImage& image, const std::string& path, const ColourSettings& colour);

// Returns the exposure used.
DisplayExposure write_render_png(const RenderImage& image, const std::string& path, const ColourSettings& colour);

// A light sweep's frames (light_sweep) as display PNGs with one exposure for all (the auto rule
// over every frame's pixels, unless the settings fix it), so that brightness changes between
// frames are real, and a contact sheet of them: a grid of ⌈√n⌉ columns, row-major, black where
// no frame falls, the frames 2 pixels apart on grey, each under a 20-pixel strip with its number
// and its first light's position in mm (white on grey, cut at the frame's width). Returns the
// exposure.
DisplayExposure write_sweep_pngs(const std::vector<RenderImage>& frames, const std::vector<std::string>& frame_paths,
                                 const std::string& sheet_path, const ColourSettings& colour);

// The caption lines of a render's PNG, from its metadata (a figure's render cell, docs/batch.md):
// the method (with the diffraction model of a wave method) and material; the wavelength or the
// spectral bins; the size, samples per pixel and the PNG's exposure with its rule.
std::vector<std::string> render_caption(const Provenance& metadata);

// The EXR's "Y" channel or R, G, B channels back, [channel][row][col], for tests and comparisons.
struct RenderExr {
    int width = 0;
    int height = 0;
    std::vector<std::string> channels;
    std::vector<float> values;
};
RenderExr load_render_exr(const std::string& path);

}  // namespace glintscope
