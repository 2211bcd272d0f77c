// Running a manifest: incremental, shardable panel computation and the assembly of the figure.
#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/md5.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/batch/batch.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/output/lobe_output.hpp"
#include "glintscope/render/render_output.hpp"
#include "glintscope/render/render_request.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/version.hpp"

namespace glintscope {
namespace {

namespace fs = std::filesystem;

fs::path figure_path(const Manifest& manifest) {
    const fs::path output(manifest.output);
    return output.is_absolute() ? output : fs::path(manifest.path).parent_path() / output;
}

std::string file_md5(const std::string& path) {
    std::ifstream stream(path, std::ios::binary);
    if (!stream) throw Error("cannot read '" + path + "'");
    const std::string bytes((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
    return md5_hex(bytes.data(), bytes.size());
}

std::string heightfield_of(const QueryText& query) {
    for (const auto& [key, value] : query)
        if (key == "heightfield") return value;
    return "";
}

// What a panel depends on: the tool's version, the method, the query text and the heightfield's
// bytes (a builtin is its name: its recipe is part of the version).
std::string panel_hash(const ManifestPanel& panel, std::map<std::string, std::string>& heightfield_hashes) {
    const std::string heightfield = heightfield_of(panel.query);
    if (!heightfield_hashes.count(heightfield))
        heightfield_hashes[heightfield] = heightfield.starts_with("builtin:") ? heightfield : file_md5(heightfield);
    std::string text = "glintscope " + version() + "\nmethod=" + panel.method + "\n";
    if (panel.render) text += "kind=render\n";
    for (const auto& [key, value] : panel.query) text += key + "=" + value + "\n";
    text += "heightfield.md5=" + heightfield_hashes[heightfield] + "\n";
    return md5_hex(text.data(), text.size());
}

bool up_to_date(const std::string& exr, const std::string& hash) {
    if (!fs::exists(exr)) return false;
    try {
        const Provenance metadata = read_output_metadata(exr);
        const auto it = metadata.find("batch.hash");
        return it != metadata.end() && it->second == hash;
    } catch (const Error&) {
        return false;  // unreadable: recompute it
    }
}

std::string panel_name(const Manifest& manifest, const ManifestPanel& panel) {
    return manifest.row_labels[panel.row] + " / " + manifest.column_labels[panel.column];
}

// A render cell as `glintscope render KEYS -o EXR --png PNG` runs it: the same request, scene,
// colour settings and writers; the PNG first, so that an EXR with the hash means both are there.
PanelReport compute_render_panel(const Manifest& manifest, const ManifestPanel& panel, const std::string& exr,
                                 const std::string& hash) {
    const RenderRequest request = render_request(panel.method, panel.query);
    const ColourSettings colour = render_colour(request);
    RenderImage image = render(render_scene(request), render_settings(request));
    image.metadata["batch.hash"] = hash;
    write_render_png(image, render_picture_path(manifest, panel), colour);
    write_render_exr(image, exr, colour);
    return {panel_name(manifest, panel), {}, std::move(image.warnings)};
}

// The panel through the one pipeline (as `lobe` runs it), with the notes and warnings to say.
PanelReport compute_panel(const Manifest& manifest, const ManifestPanel& panel, const std::string& exr,
                          const std::string& hash) {
    if (panel.render) return compute_render_panel(manifest, panel, exr, hash);
    LobeRun run = run_lobe(panel.method, make_query(panel.query));
    run.image.metadata["batch.hash"] = hash;
    LobeOutputOptions options;
    options.spectral_channels = true;  // so that the panel reads back exactly
    write_lobe_exr(run.image, exr, options);
    write_lobe_json(run.image, exr.substr(0, exr.size() - 4) + ".json", options);
    return {panel_name(manifest, panel), std::move(run.notes), std::move(run.warnings)};
}

// A BRDF panel's albedo per wavelength beside its material's Fresnel reflectance F(θ_i) (a flat
// mirror's albedo; 1 without a material) and their ratio: above 1 the method or model creates
// energy. Null for an NDF.
nlohmann::ordered_json albedo_record(const ManifestPanel& panel, const LobeImage& image) {
    if (image.quantity != Quantity::brdf) return nullptr;
    const LobeQuery query = check_query_text(panel.query);
    nlohmann::ordered_json layers = nlohmann::ordered_json::array();
    for (std::size_t layer = 0; layer < image.layers(); ++layer) {
        const double albedo = disk_sum(image, layer);
        const double f = fresnel_reflectance(query.material.name, image.wavelengths_um[layer], query.omega_i.z);
        layers.push_back({{"wavelength_um", image.wavelengths_um[layer]},
                          {"albedo", albedo},
                          {"fresnel", f},
                          {"albedo_over_fresnel", albedo / f}});
    }
    return layers;
}

// A render cell's provenance: its PNG, the exposure and rule it was shown with, and the scene
// (render.*: patch, camera, field of view, size, lights, spectrum, spp, footprint) it recorded.
nlohmann::ordered_json render_record(const Manifest& manifest, const ManifestPanel& panel, const DisplayPicture& picture) {
    nlohmann::ordered_json scene;
    for (const auto& [key, value] : picture.metadata)
        if (key.starts_with("render.")) scene[key.substr(7)] = value;
    const auto value = [&](const std::string& key) {
        const auto it = picture.metadata.find(key);
        return it == picture.metadata.end() ? std::string() : it->second;
    };
    return {{"png", render_picture_path(manifest, panel)},
            {"exposure_ev", value("output.exposure_ev")},
            {"exposure_rule", value("output.exposure_rule")},
            {"caption", picture.caption},
            {"scene", scene}};
}

void write_record(const Manifest& manifest, const std::string& path, const std::vector<LobeImage>& images,
                  const std::vector<DisplayPicture>& pictures, const std::vector<std::string>& caption) {
    nlohmann::ordered_json record;
    record["format"] = "glintscope batch";
    record["manifest"] = manifest.path;
    record["title"] = manifest.title;
    record["caption"] = caption;
    record["figure"] = figure_path(manifest).string();
    record["rows"] = manifest.row_labels;
    record["columns"] = manifest.column_labels;
    nlohmann::ordered_json panels = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < manifest.panels.size(); ++k) {
        const ManifestPanel& panel = manifest.panels[k];
        nlohmann::ordered_json query;
        for (const auto& [key, value] : panel.query) query[key] = value;
        nlohmann::ordered_json entry = {{"row", panel.row},
                                        {"column", panel.column},
                                        {"kind", panel.render ? "render" : "lobe"},
                                        {"method", panel.method},
                                        {"query", query},
                                        {"exr", panel_path(manifest, panel)}};
        if (panel.render) entry["render"] = render_record(manifest, panel, pictures[k]);
        else entry["albedo"] = albedo_record(panel, images[k]);
        panels.push_back(entry);
    }
    record["panels"] = panels;
    write_text_file(path, record.dump(2) + "\n");
}

void assemble(const Manifest& manifest, const LobeOutputOptions& output, BatchResult& result) {
    const std::size_t count = manifest.panels.size();
    std::vector<LobeImage> images(count);
    std::vector<DisplayPicture> pictures(count);
    for (std::size_t k = 0; k < count; ++k) {
        const ManifestPanel& panel = manifest.panels[k];
        if (!panel.render) {
            images[k] = load_lobe_exr(panel_path(manifest, panel));
            continue;
        }
        pictures[k] = load_display_picture(render_picture_path(manifest, panel));
        pictures[k].caption = render_caption(pictures[k].metadata);
    }
    Figure figure;
    figure.title = manifest.title;
    figure.caption = manifest.caption;
    figure.row_labels = manifest.row_labels;
    figure.column_labels = manifest.column_labels;
    figure.exposure = manifest.exposure;
    figure.style = manifest.style;
    figure.cells.assign(manifest.row_labels.size(), std::vector<const LobeImage*>(manifest.column_labels.size()));
    figure.pictures.assign(manifest.row_labels.size(), std::vector<const DisplayPicture*>(manifest.column_labels.size()));
    for (std::size_t k = 0; k < count; ++k) {
        const ManifestPanel& panel = manifest.panels[k];
        if (panel.render) figure.pictures[panel.row][panel.column] = &pictures[k];
        else figure.cells[panel.row][panel.column] = &images[k];
    }
    // Insets: each row's heightfield with the footprint of its first panel (a render's: its coherence footprint).
    std::vector<LobeQuery> row_queries;
    if (manifest.insets) {
        for (std::size_t r = 0; r < manifest.row_labels.size(); ++r) {
            const ManifestPanel& first = manifest.panels[r * manifest.column_labels.size()];
            row_queries.push_back(first.render ? render_query(render_request(first.method, first.query)) : make_query(first.query));
        }
        for (const LobeQuery& query : row_queries) figure.insets.push_back({query.field.get(), query.footprint});
    }
    result.figure_path = figure_path(manifest).string();
    LobeOutputOptions figure_output = output;
    figure_output.colour.log_scale = figure_output.colour.log_scale || manifest.log_scale;
    const FigureLayout layout = write_figure(figure, result.figure_path, figure_output);
    result.record_path = result.figure_path.substr(0, result.figure_path.size() - 4) + ".json";
    write_record(manifest, result.record_path, images, pictures, layout.caption);
    result.assembled = true;
}

}  // namespace

std::string render_picture_path(const Manifest& manifest, const ManifestPanel& panel) {
    const std::string exr = panel_path(manifest, panel);
    return exr.substr(0, exr.size() - 4) + ".png";
}

std::string panel_path(const Manifest& manifest, const ManifestPanel& panel) {
    const fs::path figure = figure_path(manifest);
    const fs::path folder = figure.parent_path() / (figure.stem().string() + ".panels");
    // Appended piece by piece: GCC 12 misreports "r" + std::to_string(...) under -Wrestrict.
    std::string name = "r";
    name.append(std::to_string(panel.row + 1)).append("-c").append(std::to_string(panel.column + 1)).append(".exr");
    return (folder / name).string();
}

BatchResult run_batch(const Manifest& manifest, const BatchOptions& options, const LobeOutputOptions& output,
                      const BatchProgress& progress) {
    if (options.shard_count < 1 || options.shard_index >= options.shard_count)
        throw Error("shard " + std::to_string(options.shard_index + 1) + "/" + std::to_string(options.shard_count) +
                    " does not exist");
    const fs::path figure = figure_path(manifest);
    check_output_path(figure.string(), {"png"}, "output");
    std::error_code ec;
    fs::create_directories(fs::path(panel_path(manifest, manifest.panels.front())).parent_path(), ec);
    if (ec) throw Error("cannot create the panel folder beside '" + figure.string() + "': " + ec.message());

    // This shard's panels (every shard_count-th, in row-major order) that need computing.
    std::map<std::string, std::string> heightfield_hashes;
    std::vector<std::pair<const ManifestPanel*, std::string>> to_compute;
    BatchResult result;
    for (std::size_t k = 0; k < manifest.panels.size(); ++k) {
        if (k % options.shard_count != options.shard_index) continue;
        const ManifestPanel& panel = manifest.panels[k];
        const std::string hash = panel_hash(panel, heightfield_hashes);
        const bool written = up_to_date(panel_path(manifest, panel), hash) &&
                             (!panel.render || fs::exists(render_picture_path(manifest, panel)));
        if (!options.force && written)
            ++result.up_to_date;
        else
            to_compute.emplace_back(&panel, hash);
    }

    // --jobs panels at once; each still uses the worker threads for its own loops.
    std::atomic<std::size_t> next{0}, done{0};
    std::mutex mutex;
    std::exception_ptr failure;
    std::vector<PanelReport> reports(to_compute.size());
    const auto work = [&] {
        for (std::size_t k; (k = next++) < to_compute.size();) {
            const auto& [panel, hash] = to_compute[k];
            try {
                PanelReport report = compute_panel(manifest, *panel, panel_path(manifest, *panel), hash);
                std::lock_guard lock(mutex);
                reports[k] = std::move(report);
            } catch (...) {
                std::lock_guard lock(mutex);
                if (!failure) failure = std::current_exception();
                next = to_compute.size();
            }
            std::lock_guard lock(mutex);
            if (progress)
                progress(++done, to_compute.size(),
                         panel_name(manifest, *panel));
        }
    };
    std::vector<std::thread> workers;
    const int threads = thread_count();  // the caller's, for each job's parallel loops
    for (int j = 1; j < std::min<int>(options.jobs, int(to_compute.size())); ++j)
        workers.emplace_back([&] {
            const ThreadScope inherited(threads);
            work();
        });
    work();
    for (std::thread& worker : workers) worker.join();
    if (failure) std::rethrow_exception(failure);
    result.computed = to_compute.size();
    for (PanelReport& report : reports)
        if (!report.notes.empty() || !report.warnings.empty()) result.panels.push_back(std::move(report));
    if (options.shard_count == 1) assemble(manifest, output, result);
    return result;
}

}  // namespace glintscope
