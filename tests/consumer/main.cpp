// A renderer's use of glintscope (docs/renderer.md): load a heightfield, build the BSDF of one
// footprint, evaluate and sample it. Exits 1 with a line on stderr if an answer breaks the
// contract: the sampled pdf differs from pdf(), or the mean weight from the albedo.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "glintscope/glintscope.hpp"

int main(int argc, char** argv) {
    using namespace glintscope;
    try {
        // A heightfield file (the isotropic builtin written to one, when none is given).
        std::filesystem::path path = argc > 1 ? argv[1] : std::filesystem::temp_directory_path() / "consumer.npy";
        if (argc < 2) save_heightfield(path.string(), generate_builtin("isotropic"));
        LobeQuery query;
        set_heightfield(query, load_heightfield(path.string()));
        query.footprint.centre_um = query.field->centre_um();
        query.footprint.sigma_um = 10.0;
        query.wavelengths_um = {0.45, 0.55, 0.65};
        query.resolution = 64;

        const Bsdf bsdf = make_bsdf("geometric", query);
        const Vec3 omega_i = direction_from_spherical(0.5, 0.0);
        const Vec3 mirror{-omega_i.x, -omega_i.y, omega_i.z};
        std::printf("f_r at the mirror direction: %g sr^-1\n", bsdf.eval(omega_i, mirror)[0]);

        double mean = 0.0;
        const int samples = 100000;
        for (int k = 0; k < samples; ++k) {
            // A renderer's sampler would supply these; a fixed lattice suffices here.
            const double u1 = (k + 0.5) / samples, u2 = std::fmod(0.6180339887498949 * k, 1.0);
            const BsdfSample s = bsdf.sample(omega_i, u1, u2);
            if (s.pdf > 0.0 && std::fabs(s.pdf - bsdf.pdf(omega_i, s.omega_o)) > 1e-9 * s.pdf) {
                std::fprintf(stderr, "sample %d: pdf %g, pdf() %g\n", k, s.pdf, bsdf.pdf(omega_i, s.omega_o));
                return 1;
            }
            mean += s.weight[0] / samples;
        }
        const double albedo = bsdf.albedo(omega_i)[0];
        std::printf("albedo %g, mean sampling weight %g\n", albedo, mean);
        if (!(std::fabs(mean - albedo) < 0.01 * albedo)) {
            std::fprintf(stderr, "mean weight %g differs from albedo %g by more than 1%%\n", mean, albedo);
            return 1;
        }
        return 0;
    } catch (const Error& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}
