// Batch figures: manifests checked before work, incremental panels, shards that assemble the
// same figure as one run, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "glintscope/batch/batch.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/render/render_output.hpp"
#include "glintscope/render/render_request.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

void write_file(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string read_bytes(const std::string& path) {
    std::ifstream stream(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
}

// A 64² rough field and a 2 × 2 manifest over it (two incident angles × two methods).
std::string small_manifest(const TemporaryDirectory& directory, const std::string& extra_row = "") {
    Heightfield field = make_heightfield(64, 64, 0.5);
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) field.at(r, c) = float(0.2 * std::sin(0.4 * c) * std::cos(0.3 * r));
    // Written once: OpenImageIO stamps each EXR with the time, so a rewrite changes the file's MD5
    // (which the panel hashes include) whenever a second has passed.
    if (!std::filesystem::exists(directory.file("rough.exr"))) save_heightfield(directory.file("rough.exr"), field);
    const std::string manifest = directory.file("figure.toml");
    write_file(manifest, R"(title = "Small test figure"
output = "figure.png"
exposure = "shared-per-row"
[defaults]
heightfield = "rough.exr"
sigma_c = "3um"
res = 32
[[row]]
label = "normal"
incident = [0, 0]
[[row]]
label = "oblique")" + extra_row + R"(
incident = [30, 0]
[[column]]
label = "gabor"
method = "gabor"
kernels_per_texel = 1
[[column]]
label = "fft"
method = "fft"
)");
    return manifest;
}

TEST(Batch, TheFigureHasOnePanelPerCellAndRerunsComputeNothing) {
    TemporaryDirectory directory;
    const Manifest manifest = load_manifest(small_manifest(directory));
    ASSERT_EQ(manifest.panels.size(), 4u);
    EXPECT_EQ(manifest.panels[2].method, "gabor");  // row-major: (row 2, column 1)
    const BatchResult first = run_batch(manifest, {}, {});
    EXPECT_EQ(first.computed, 4u);
    ASSERT_TRUE(first.assembled);
    OIIO::ImageBuf figure(first.figure_path);
    ASSERT_TRUE(figure.read());
    // Two panel widths at least (each ≥ the 320-pixel disk), two rows of panels.
    EXPECT_GE(figure.spec().width, 2 * panel_size(32));
    EXPECT_GE(figure.spec().height, 2 * panel_size(32));
    // The record holds each panel's albedo (its EXR's disk sum) and albedo/F (no material: F = 1).
    std::ifstream record_stream(first.record_path);
    const nlohmann::json record = nlohmann::json::parse(record_stream);
    for (std::size_t k = 0; k < manifest.panels.size(); ++k) {
        const nlohmann::json& albedo = record["panels"][k]["albedo"][0];
        EXPECT_NEAR(albedo["albedo"].get<double>(), disk_sum(load_lobe_exr(panel_path(manifest, manifest.panels[k]))), 1e-12);
        EXPECT_EQ(albedo["fresnel"].get<double>(), 1.0);
        EXPECT_EQ(albedo["albedo_over_fresnel"], albedo["albedo"]);
    }
    const BatchResult again = run_batch(manifest, {}, {});
    EXPECT_EQ(again.computed, 0u);
    EXPECT_EQ(again.up_to_date, 4u);
    EXPECT_EQ(read_bytes(again.figure_path), read_bytes(first.figure_path));
}

TEST(Batch, ChangingOneParameterRecomputesExactlyThePanelsItReaches) {
    TemporaryDirectory directory;
    run_batch(load_manifest(small_manifest(directory)), {}, {});
    // A key of the oblique row reaches its two panels, and nothing else.
    EXPECT_EQ(run_batch(load_manifest(small_manifest(directory, "\nlambda = \"0.6um\"")), {}, {}).computed, 2u);
    // A key of the fft column alone, in that same state, reaches one panel per row; one method
    // option of one column in a one-row figure reaches exactly one panel.
    std::string text = read_bytes(directory.file("figure.toml"));
    text.replace(text.find("method = \"fft\""), 14, "method = \"fft\"\nwindow = 5");
    const std::size_t oblique = text.find("[[row]]\nlabel = \"oblique\"");
    text.erase(oblique, text.find("[[column]]") - oblique);  // one row left: normal incidence
    write_file(directory.file("figure.toml"), text);
    EXPECT_EQ(run_batch(load_manifest(directory.file("figure.toml")), {}, {}).computed, 1u);
}

TEST(Batch, TwoShardsAssembleTheSameFigureAsOneRun) {
    TemporaryDirectory one, two;
    const BatchResult single = run_batch(load_manifest(small_manifest(one)), {}, {});
    const Manifest manifest = load_manifest(small_manifest(two));
    const BatchResult first = run_batch(manifest, {0, 2, false, 1}, {});
    const BatchResult second = run_batch(manifest, {1, 2, false, 1}, {});
    EXPECT_FALSE(first.assembled);
    EXPECT_EQ(first.computed + second.computed, 4u);
    const BatchResult assembled = run_batch(manifest, {}, {});
    EXPECT_EQ(assembled.computed, 0u);
    EXPECT_EQ(read_bytes(assembled.figure_path), read_bytes(single.figure_path));
}

std::string manifest_error(const std::string& text) {
    TemporaryDirectory directory;
    write_file(directory.file("m.toml"), text);
    try {
        load_manifest(directory.file("m.toml"));
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Batch, MalformedManifestsNameFileLineAndKey) {
    const std::string head = "output = \"f.png\"\n[[row]]\nlabel = \"a\"\nheightfield = \"builtin:grating\"\n";
    const std::string column = "[[column]]\nlabel = \"b\"\n";
    EXPECT_NE(manifest_error(head + column + "colour = \"red\"\n").find("m.toml:7: key 'colour': unknown key"),
              std::string::npos);
    EXPECT_NE(manifest_error(head + column + "res = { a = 1 }\n").find("m.toml:7: key 'res'"), std::string::npos);
    EXPECT_NE(manifest_error(head + column + "res = \"many\"\n").find("query key res"), std::string::npos);
    EXPECT_NE(manifest_error("output = \"f.png\"\n[[row]]\nlabel = \"a\"\nheightfield = \"nothere.exr\"\n" + column)
                  .find("heightfield 'nothere.exr' does not exist"),
              std::string::npos);
    EXPECT_NE(manifest_error(head).find("no [[column]]"), std::string::npos);
    EXPECT_NE(manifest_error(head + column + "method = \"raytrace\"\n").find("unknown method 'raytrace'"),
              std::string::npos);
    EXPECT_NE(manifest_error("output = \"f.png\"\n[[row\n").find("m.toml:2:"), std::string::npos);
    EXPECT_NE(manifest_error("scale = \"sideways\"\n" + head + column).find("m.toml:1: key 'scale': 'sideways' is not linear or log"),
              std::string::npos);
    EXPECT_NE(manifest_error(head + column + "method = \"pndf\"\n").find("does not compute brdf"), std::string::npos);
    EXPECT_NE(manifest_error("style = \"poster\"\n" + head + column).find("m.toml:1: key 'style': 'poster' is not standard or paper"),
              std::string::npos);
    EXPECT_NE(manifest_error("exposure = \"per-panel\"\nstyle = \"paper\"\n" + head + column).find("m.toml:2: key 'style'"),
              std::string::npos);
    // The line the value is written on: in [defaults], and a material's name.
    EXPECT_NE(manifest_error("output = \"f.png\"\n[defaults]\nsigma_c = 5\nres = \"big\"\n" + head.substr(head.find('\n') + 1) + column)
                  .find("m.toml:4: key 'res': query key res"),
              std::string::npos);
    const std::string material = manifest_error(head + column + "material = \"Xx\"\n");
    EXPECT_NE(material.find("m.toml:7: key 'material'"), std::string::npos) << material;
    EXPECT_NE(material.find("unknown material 'Xx'"), std::string::npos) << material;
}

TEST(Batch, APaperFigureHasOneColourBarPerRowAndItsRecordCarriesTheSharedLegend) {
    TemporaryDirectory directory;
    const std::string text = read_bytes(small_manifest(directory));
    write_file(directory.file("figure.toml"), "style = \"paper\"\n" + text);
    const Manifest manifest = load_manifest(directory.file("figure.toml"));
    EXPECT_EQ(manifest.style, FigureStyle::paper);
    const BatchResult result = run_batch(manifest, {}, {});
    const nlohmann::json record = nlohmann::json::parse(read_bytes(result.record_path));
    const std::vector<std::string> caption = record["caption"];
    EXPECT_NE(std::find(caption.begin(), caption.end(), "rings: theta_o 30, 60 deg; cyan: mirror direction"), caption.end());
    // The layout behind the PNG: one bar per row (the panels are the record's images).
    std::vector<LobeImage> images;
    for (const ManifestPanel& panel : manifest.panels) images.push_back(load_lobe_exr(panel_path(manifest, panel)));
    Figure figure;
    figure.style = FigureStyle::paper;
    figure.cells.assign(manifest.row_labels.size(), std::vector<const LobeImage*>(manifest.column_labels.size()));
    for (std::size_t k = 0; k < manifest.panels.size(); ++k)
        figure.cells[manifest.panels[k].row][manifest.panels[k].column] = &images[k];
    const FigureLayout layout = write_figure(figure, directory.file("again.png"), {});
    EXPECT_EQ(layout.colour_bars.size(), manifest.row_labels.size());
    EXPECT_EQ(layout.caption, caption);
}

TEST(Batch, InsetsAddAHeightfieldColumnWithTheFootprintDrawn) {
    // The same figure with insets = true: one more column to the left of the panels, holding the
    // row's heightfield (viridis, not grey) with the footprint's magenta circle at its centre;
    // nothing is recomputed for it.
    TemporaryDirectory directory;
    const BatchResult plain = run_batch(load_manifest(small_manifest(directory)), {}, {});
    // Kept under another name: the second run rewrites the figure (and OpenImageIO caches by name).
    std::filesystem::copy_file(plain.figure_path, directory.file("plain.png"));
    std::string text = read_bytes(directory.file("figure.toml"));
    write_file(directory.file("figure.toml"), "insets = true\n" + text);
    const BatchResult inset = run_batch(load_manifest(directory.file("figure.toml")), {}, {});
    EXPECT_EQ(inset.computed, 0u);
    OIIO::ImageBuf before(directory.file("plain.png")), after(inset.figure_path);
    ASSERT_TRUE(before.read() && after.read());
    EXPECT_GT(after.spec().width, before.spec().width + 100);
    EXPECT_EQ(after.spec().height, before.spec().height);
    int magenta = 0;
    for (int y = 0; y < after.spec().height; ++y)
        for (int x = 0; x < after.spec().width - before.spec().width; ++x) {
            float pixel[3];
            after.getpixel(x, y, pixel, 3);
            if (pixel[0] > 0.9f && pixel[1] < 0.3f && pixel[2] > 0.4f && pixel[2] < 0.7f) ++magenta;
        }
    EXPECT_GT(magenta, 20);  // the footprint circles of both rows
    EXPECT_NE(manifest_error("insets = \"yes\"\noutput = \"f.png\"\n").find("m.toml:1: key 'insets': expected true or false"),
              std::string::npos);
}

// The label text is drawn: the figure with labels differs from the one without exactly where the
// label's rendered text lies (its width as OpenImageIO measures the text alone).
// The paper-figure manifests the scripts run: each loads, and each panel's query plans (method,
// query, footprint, options) as a run would, so that a stale key fails here and not mid-figure.
TEST(Batch, EveryManifestUnderFiguresLoadsAndPlans) {
    int manifests = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(GLINTSCOPE_SOURCE_DIR) + "/figures")) {
        if (entry.path().extension() != ".toml") continue;
        ++manifests;
        const Manifest manifest = load_manifest(entry.path().string());
        EXPECT_FALSE(manifest.panels.empty()) << entry.path();
        for (const ManifestPanel& panel : manifest.panels) {
            if (panel.render)  // the scene validated with its heightfield, the method planned (render.hpp validate)
                EXPECT_NO_THROW(render_scene(render_request(panel.method, panel.query)))
                    << entry.path() << ": " << manifest.row_labels[panel.row] << " / " << manifest.column_labels[panel.column];
            else
                EXPECT_NO_THROW(plan_lobe(panel.method, make_query(panel.query)))
                    << entry.path() << ": " << manifest.row_labels[panel.row] << " / " << manifest.column_labels[panel.column];
        }
    }
    EXPECT_GE(manifests, 4);
}

TEST(Figure, LabelsAreDrawnWhereAndAsWideAsTheTextAlone) {
    TemporaryDirectory directory;
    LobeImage lobe = make_lobe_image(32, {0.5});
    lobe.at(0, 16, 16) = 1.0f;
    Figure figure;
    figure.cells = {{&lobe}};
    figure.column_labels = {""};
    write_figure(figure, directory.file("plain.png"), {});
    figure.column_labels = {"A column label"};
    write_figure(figure, directory.file("labelled.png"), {});
    OIIO::ImageBuf plain(directory.file("plain.png")), labelled(directory.file("labelled.png"));
    ASSERT_TRUE(plain.read() && labelled.read());
    ASSERT_EQ(plain.spec().width, labelled.spec().width);
    const OIIO::ROI changed = OIIO::ImageBufAlgo::nonzero_region(OIIO::ImageBufAlgo::absdiff(plain, labelled));
    ASSERT_TRUE(changed.defined());
    const OIIO::ROI text = OIIO::ImageBufAlgo::text_size("A column label", 14, "DejaVuSans");
    EXPECT_NEAR(changed.width(), text.width(), 3);
    EXPECT_LT(changed.ybegin, 60);  // in the header, above the panel
}

}  // namespace
}  // namespace glintscope

namespace glintscope {
namespace {

// A small periodic field (16 um tiles) and a 1 x 2 figure of render cells over it: the light
// opposite the camera, whose mirror point is the patch's centre, seen at 2 degrees.
std::string render_manifest(const TemporaryDirectory& directory) {
    Heightfield field = make_heightfield(32, 32, 0.5);
    for (int r = 0; r < 32; ++r)
        for (int c = 0; c < 32; ++c)
            field.at(r, c) = float(0.15 * std::sin(2.0 * pi * c / 32.0) * std::cos(4.0 * pi * r / 32.0));
    save_heightfield(directory.file("tile.exr"), field);
    const std::string manifest = directory.file("renders.toml");
    write_file(manifest, R"(title = "Render cells"
output = "renders.png"
[defaults]
kind = "render"
heightfield = "tile.exr"
periodic = "yes"
size = "24x14"
fov = 2
spp = 1
light = ["0,7cm,7cm:1", "1mm,7cm,7.1cm:0.5"]
[[row]]
label = "tile"
[[column]]
label = "0.5 um"
method = "gabor"
lambda = "0.5um"
sigma_c = "4um"
[[column]]
label = "spectral"
method = "gabor"
spectral = 3
sigma_c = "4um"
exposure = 1.5
)");
    return manifest;
}

std::vector<std::uint8_t> png_pixels(const std::string& path) {
    auto input = OIIO::ImageInput::open(path);
    EXPECT_TRUE(input) << path;
    if (!input) return {};
    std::vector<std::uint8_t> pixels(std::size_t(input->spec().width) * input->spec().height * 3);
    input->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data());
    return pixels;
}

// A render cell is `glintscope render` of its keys: the same EXR values and PNG pixels, bit for
// bit, for one wavelength and a spectrum with a given exposure; the record names its scene and
// exposure, and a rerun computes nothing.
TEST(BatchRender, ARenderCellIsTheRenderCommandsOutputForTheSameOptions) {
    TemporaryDirectory directory;
    const Manifest manifest = load_manifest(render_manifest(directory));
    ASSERT_EQ(manifest.panels.size(), 2u);
    EXPECT_TRUE(manifest.panels[0].render);
    const BatchResult result = run_batch(manifest, {}, {});
    ASSERT_TRUE(result.assembled);
    const std::vector<std::vector<std::string>> flags = {{"--lambda", "0.5um"}, {"--spectral", "3", "--exposure", "1.5"}};
    for (std::size_t k = 0; k < 2; ++k) {
        const std::string exr = directory.file("cli" + std::to_string(k) + ".exr"), png = directory.file("cli" + std::to_string(k) + ".png");
        std::vector<std::string> arguments = {"render", directory.file("tile.exr"), "--periodic", "--size", "24x14",
                                              "--fov", "2", "--spp", "1", "--light", "0,7cm,7cm:1", "--light",
                                              "1mm,7cm,7.1cm:0.5", "--sigma-c", "4um", "-o", exr, "--png", png};
        arguments.insert(arguments.end(), flags[k].begin(), flags[k].end());
        const auto cli = testing::run_cli(arguments);
        ASSERT_EQ(cli.exit_code, 0) << cli.output;
        const RenderExr expected = load_render_exr(exr), cell = load_render_exr(panel_path(manifest, manifest.panels[k]));
        EXPECT_EQ(cell.channels, expected.channels);
        EXPECT_EQ(cell.values, expected.values);
        EXPECT_GT(*std::max_element(expected.values.begin(), expected.values.end()), 0.0f);
        EXPECT_EQ(png_pixels(render_picture_path(manifest, manifest.panels[k])), png_pixels(png));
    }
    std::ifstream record_stream(result.record_path);
    const nlohmann::json record = nlohmann::json::parse(record_stream);
    const nlohmann::json& spectral = record["panels"][1];
    EXPECT_EQ(spectral["kind"], "render");
    EXPECT_EQ(spectral["render"]["exposure_ev"], "1.5");
    EXPECT_EQ(spectral["render"]["scene"]["size"], "24x14");
    EXPECT_EQ(spectral["render"]["scene"]["lights_um_w_per_sr"], "0,70000,70000:1;1000,70000,71000:0.5");
    EXPECT_EQ(spectral["query"]["spectral"], "3");
    EXPECT_EQ(run_batch(manifest, {}, {}).computed, 0u);
}

// A bad render option fails at the line it is written on, in one line naming the key; a lobe key
// in a render cell and a render key in a lobe cell name the cell.
TEST(BatchRender, ABadRenderOptionIsRefusedAtItsLine) {
    const std::string head = "output = \"f.png\"\n[[row]]\nlabel = \"a\"\nheightfield = \"builtin:grating\"\n";
    const std::string column = "[[column]]\nlabel = \"b\"\nkind = \"render\"\n";
    for (const auto& [line, key] : std::vector<std::pair<std::string, std::string>>{
             {"fov = 0", "fov"},
             {"camera = \"0,-1cm,-1cm:0,0,0\"", "camera"},
             {"light = [\"0,1cm,1cm:1\", \"0,1cm,-1cm:1\"]", "light"},
             {"size = \"1000000x10\"", "size"},
             {"spp = 3", "spp"},
             {"colour_space = \"sRGB\"", "colour_space"},
             {"exposure = \"bright\"", "exposure"}}) {
        const std::string error = manifest_error(head + column + line + "\n");
        EXPECT_NE(error.find("m.toml:8: key '" + key + "'"), std::string::npos) << line << ": " << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    }
    EXPECT_NE(manifest_error(head + column + "res = 64\n").find("query key 'res' does not apply to a render"),
              std::string::npos);
    EXPECT_NE(manifest_error(head + column + "method = \"stam\"\n").find("cannot answer a BSDF per shading point"),
              std::string::npos);
    EXPECT_NE(manifest_error(head + "[[column]]\nlabel = \"b\"\nfov = 20\n").find("set kind = \"render\""),
              std::string::npos);
    EXPECT_NE(manifest_error(head + column + "kind = \"movie\"\n").find("m.toml:8"), std::string::npos);
}

// scripts/reproduce-figures.sh patch: Yan 2018 Fig. 12's grid, 3 surfaces x (8-bin spectral,
// 0.4 um, geometric), every cell a render of the Patch scene's camera and light in Al.
TEST(BatchRender, ThePatchManifestHasNineRenderCells) {
    const Manifest manifest = load_manifest(std::string(GLINTSCOPE_SOURCE_DIR) + "/figures/patch.toml");
    ASSERT_EQ(manifest.panels.size(), 9u);
    EXPECT_EQ(manifest.row_labels, (std::vector<std::string>{"isotropic", "brushed", "scratched"}));
    for (const ManifestPanel& panel : manifest.panels) {
        EXPECT_TRUE(panel.render);
        const RenderRequest request = render_request(panel.method, panel.query);
        const Scene view = render_view(request);
        EXPECT_EQ(view.camera.width, 320);
        EXPECT_EQ(view.camera.height, 180);
        EXPECT_EQ(request.heightfield, "builtin:" + manifest.row_labels[panel.row]);
        const LobeQuery query = check_query_text(render_query_text(request));
        EXPECT_EQ(query.material.name, "Al");
        const std::vector<std::size_t> bins = {8, 1, 1};
        EXPECT_EQ(panel.method, panel.column == 2 ? "geometric" : "gabor");
        EXPECT_EQ(query.wavelengths_um.size(), bins[panel.column]);
        if (panel.column == 1) EXPECT_DOUBLE_EQ(query.wavelengths_um[0], 0.4);
    }
}

}  // namespace
}  // namespace glintscope
