#pragma once
// What a method author writes: one MethodEntry, declared in the method's own file, and one line
// in the method table (lib/src/pipeline/method_table.cpp). The pipeline does the generic work, so
// a method's compute function sees a validated query with its supersampling resolved and only its
// own option keys.
#include <string>

#include "glintscope/lobe/method_info.hpp"
#include "glintscope/lobe/query.hpp"
#include "lobe/point_answers.hpp"

namespace glintscope {

using MethodFunction = LobeImage (*)(const LobeQuery&);
using PointFunction = PointAnswers (*)(const LobeQuery&);
using PointFieldFunction = PointAnswersAt (*)(const LobeQuery&);

struct MethodEntry {
    MethodInfo info;
    MethodFunction compute = nullptr;  // answers every quantity in info.quantities
    PointFunction point = nullptr;     // brdf for single directions; none: from the images (bsdf/)
    PointFieldFunction point_field = nullptr;  // the same for any footprint, built once per heightfield
    // Whether make_bsdf answers one footprint with `point` (or, without it, its images) although
    // the method has a point field: a field that only evaluates (no sampler), or answers the
    // continuous lobe where the images integrate over pixels, serves one-off footprints (renderers,
    // BsdfField), while a footprint's own Bsdf keeps its own eval, sampler and pdf.
    bool bsdf_from_images = false;
};

// Method options as values, with defaults when absent; each throws Error naming the option.
double method_option_number(const LobeQuery& query, const std::string& key, double fallback);
double method_option_length_um(const LobeQuery& query, const std::string& key, double fallback);
int method_option_integer(const LobeQuery& query, const std::string& key, int fallback, int min, int max);
std::string method_option_text(const LobeQuery& query, const std::string& key, const std::string& fallback);

}  // namespace glintscope
