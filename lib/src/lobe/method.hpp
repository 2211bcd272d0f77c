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
    // brdf for single directions at one footprint, what make_bsdf answers with; a method may
    // return none (e.g. for settings it answers only through its images).
    PointFunction point = nullptr;
    // The same for any footprint, built once per heightfield (BsdfField: renderers' one-off
    // footprints); make_bsdf uses it only for a method without `point`. Without either, a BSDF
    // answers from the method's images (bsdf/).
    PointFieldFunction point_field = nullptr;
};

// Method options as values, with defaults when absent; each throws Error naming the option.
double method_option_number(const LobeQuery& query, const std::string& key, double fallback);
double method_option_length_um(const LobeQuery& query, const std::string& key, double fallback);
int method_option_integer(const LobeQuery& query, const std::string& key, int fallback, int min, int max);
std::string method_option_text(const LobeQuery& query, const std::string& key, const std::string& fallback);

}  // namespace glintscope
