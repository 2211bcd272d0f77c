#pragma once
// Comparison figures from a TOML manifest: rows × columns of panels, each panel a query (the
// query keys of query_keys.hpp plus `method`), merged from [defaults], its [[row]] and its
// [[column]] (later ones win). Panels are computed once and kept beside the figure with a
// content hash (method, query, heightfield bytes, version), so a rerun recomputes only what
// changed; `shard` splits the panels deterministically so that a cluster can compute them in
// parallel and a final run assembles the figure. docs/batch.md has the manifest reference.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "glintscope/output/figure.hpp"
#include "glintscope/lobe/query_keys.hpp"

namespace glintscope {

struct ManifestPanel {
    std::size_t row = 0;
    std::size_t column = 0;
    std::string method;
    QueryText query;      // without `method`; a render cell's also holds its render keys (render_request.hpp)
    bool render = false;  // kind = "render": the cell is `glintscope render` of its keys, not a lobe
};

struct Manifest {
    std::string path;
    std::string title;
    std::string caption;
    std::string output;  // the figure's PNG, relative to the manifest's folder unless absolute
    SharedExposure exposure = SharedExposure::per_row;
    bool log_scale = false;  // scale = "log": panels on a log scale (NDFs with sharp folds)
    bool insets = false;     // insets = true: each row's heightfield with its footprint on the left
    FigureStyle style = FigureStyle::standard;  // style = "paper": larger type, a colour bar per row
    std::vector<std::string> row_labels;
    std::vector<std::string> column_labels;
    std::vector<ManifestPanel> panels;  // row-major
};

// Reads and checks a manifest before any computation: TOML syntax, known keys, value types,
// every panel's query keys and values, its method and quantity, and its heightfield (a
// builtin kind or an existing file); a render cell's scene and colour options as the render
// command checks them. Errors are one line: "FILE:LINE: key 'K': problem".
Manifest load_manifest(const std::string& path);

struct BatchOptions {
    std::size_t shard_index = 0;  // 0-based; with shard_count = 1, every panel
    std::size_t shard_count = 1;
    bool force = false;           // recompute panels that are up to date
    int jobs = 1;                 // panels computed at once
};

// What the pipeline said about one computed panel ("row / column"), in panel order.
struct PanelReport {
    std::string panel;
    std::vector<std::string> notes;
    std::vector<std::string> warnings;
};

struct BatchResult {
    std::size_t computed = 0;
    std::vector<PanelReport> panels;  // computed panels with notes or warnings
    std::size_t up_to_date = 0;
    bool assembled = false;       // the figure was written (a full run, not a shard)
    std::string figure_path;
    std::string record_path;      // the JSON recording every panel's query
};

using BatchProgress = std::function<void(std::size_t done, std::size_t total, const std::string& what)>;

// Computes the panels of this shard that are missing or out of date and, in a full run,
// assembles the figure from the panel files (so a sharded and a single run give the same bits).
BatchResult run_batch(const Manifest& manifest, const BatchOptions& options, const LobeOutputOptions& output,
                      const BatchProgress& progress = {});

// Where a panel's EXR lives: "<figure stem>.panels/r<row>-c<column>.exr" beside the figure. A
// render cell's EXR is the render command's -o output; its display PNG (--png) is beside it,
// render_picture_path.
std::string panel_path(const Manifest& manifest, const ManifestPanel& panel);
std::string render_picture_path(const Manifest& manifest, const ManifestPanel& panel);

}  // namespace glintscope
