#pragma once
// The core API of glintscope in one include: heightfields (load, generate, prepare), the lobe
// query and image, the methods and the pipeline that runs them, comparison, and the BSDF contract
// for renderers (docs/renderer.md). Headers that serve the command line (query keys as text,
// output writers, colour, batch manifests, validation reports, maps, fits) are included apart.
#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/version.hpp"
#include "glintscope/surface/heightfield.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "glintscope/surface/statistics.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/prepare/prepare.hpp"
#include "glintscope/optics/diffraction_model.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/lobe/footprint.hpp"
#include "glintscope/lobe/image.hpp"
#include "glintscope/lobe/method_info.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/lobe/compare.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/bsdf/bsdf.hpp"
