#pragma once
// Text ↔ query: one table of keys (heightfield, centre, sigma_c, incident, lambda, model, ...)
// that sets a LobeQuery from text, writes it back, and rebuilds it from an output's metadata,
// on the pattern of the recipe keys of `generate`. The CLI flags of `lobe` and `ndf` are
// generated from this table, and every output records its query in these keys ("query.<key>"),
// so any file the tool wrote can be re-run.
#include <string>
#include <utility>
#include <vector>

#include "glintscope/lobe/query.hpp"

namespace glintscope {

struct QueryKey {
    std::string name;        // e.g. "sigma_c"
    std::string value_name;  // e.g. "LENGTH", "THETA,PHI"
    std::string help;        // one line, with the default
    std::string implicit;    // value when given without one (e.g. spectral → "16"); empty: required
};

// Every key, in the order they are applied. Method options are the keys "option.KEY".
const std::vector<QueryKey>& query_keys();

// Ordered key/value text; a key may appear once.
using QueryText = std::vector<std::pair<std::string, std::string>>;

// Builds a query from text: applies every key (errors name the key), loads the heightfield
// (a file with its load options, or builtin:KIND), and centres the footprint on the heightfield
// when no centre is given. Keys that exclude each other (incident / incident_xy / omega_i,
// lambda / spectral) may not be combined.
LobeQuery make_query(const QueryText& text);

// The checks of make_query that need no heightfield (known keys, exclusions, every value's
// syntax and range where a key can tell), for validating manifests before any work. Returns the
// query with every key applied and no heightfield loaded.
LobeQuery check_query_text(const QueryText& text);

// One key's value checked alone, as check_query_text checks it (syntax and range; a material
// name against the known ones), so that a manifest names the line the value is written on.
// Throws Error "query key K: problem"; method options ("option.K") and unknown keys pass.
void check_query_value(const std::string& key, const std::string& value);

// The keys that reproduce the query exactly (omega_i and lambda as exact numbers).
QueryText query_text(const LobeQuery& query);

// `base` with `overrides` applied: each override replaces the base key and the keys it excludes.
QueryText merge_query_text(const QueryText& base, const QueryText& overrides);

// The query as metadata: "query.<key>" for query_text, plus the heightfield's size, texel and
// provenance ("heightfield.*") and readable angles ("info.theta_i_deg", "info.phi_i_deg").
Provenance describe_query(const LobeQuery& query);

// The query keys recorded in an output's metadata (the inverse of describe_query's "query.*").
QueryText query_text_from_metadata(const Provenance& metadata);

// The metadata of a file the tool wrote: the "glintscope:" attributes of an EXR or PNG, or the
// "metadata" object of a JSON sidecar.
Provenance read_output_metadata(const std::string& path);

// A query recorded in an output the tool wrote (EXR, PNG or JSON), with `overrides` applied, and
// the method recorded there (empty if none). A relative heightfield path is read relative to the
// record when it exists there. Throws Error when the heightfield's bytes differ from the recorded
// MD5 (unless `allow_changed_heightfield` or an override names another heightfield).
struct RecordedRun {
    std::string method;
    LobeQuery query;
};
RecordedRun recorded_run(const std::string& record_path, const QueryText& overrides, bool allow_changed_heightfield);

// A heightfield argument: a file read with `load`, or builtin:KIND (generate.hpp).
Heightfield load_heightfield_source(const HeightfieldSource& source);

}  // namespace glintscope
