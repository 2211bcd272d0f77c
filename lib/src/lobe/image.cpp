#include "glintscope/lobe/image.hpp"

#include <algorithm>

#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {

std::string to_string(Quantity quantity) { return quantity == Quantity::brdf ? "brdf" : "ndf"; }

Quantity parse_quantity(const std::string& name) {
    if (name == "brdf") return Quantity::brdf;
    if (name == "ndf") return Quantity::ndf;
    throw Error("unknown quantity '" + name + "' (available: brdf, ndf)");
}

const QuantityLabels& labels(Quantity quantity) {
    static const QuantityLabels brdf{"f_r", "sr^-1", "Y", "omega_o", "albedo",
                                     "f_r(omega_i, omega_o) [sr^-1] over the projected disk of omega_o"};
    static const QuantityLabels ndf{"D", "1", "D", "h", "normalisation",
                                    "D(h) over the projected disk of normals h (sum D (2/N)^2 = 1)"};
    return quantity == Quantity::brdf ? brdf : ndf;
}

std::span<const float> layer_values(const LobeImage& image, std::size_t layer) {
    const std::size_t pixels = std::size_t(image.resolution) * image.resolution;
    return std::span<const float>(image.values).subspan(layer * pixels, pixels);
}

double disk_sum(std::span<const float> layer, int resolution) {
    double sum = 0.0;
    for (int row = 0; row < resolution; ++row)
        for (int col = 0; col < resolution; ++col)
            if (inside_unit_disk(disk_pixel_point(row, col, resolution))) sum += layer[std::size_t(row) * resolution + col];
    return sum * disk_pixel_area(resolution);  // conventions.md: (2/N)² is a pixel's area on the projected disk
}

double disk_sum(const LobeImage& image, std::size_t layer) { return disk_sum(layer_values(image, layer), image.resolution); }

LobeImage make_lobe_image(int resolution, const std::vector<double>& wavelengths_um, Quantity quantity) {
    LobeImage image;
    image.resolution = resolution;
    image.quantity = quantity;
    image.wavelengths_um = wavelengths_um;
    image.values.assign(wavelengths_um.size() * resolution * static_cast<std::size_t>(resolution), 0.0f);
    return image;
}

void store_subpixel_means(LobeImage& image, std::size_t layer, const std::vector<double>& pixel_sums, int supersample) {
    const int n = image.resolution;
    const double inverse_count = 1.0 / (double(supersample) * supersample);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
            image.at(layer, r, c) = inside_unit_disk(disk_pixel_point(r, c, n))
                                        ? static_cast<float>(pixel_sums[std::size_t(r) * n + c] * inverse_count)
                                        : 0.0f;
}

void fill_by_direction(LobeImage& image, std::size_t layer, int supersample,
                       const std::function<double(DiskPoint)>& value) {
    const int n = image.resolution;
    std::vector<double> pixel_sums(std::size_t(n) * n);
    parallel_for(n, 4, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < n; ++c) {
                double sum = 0.0;
                for (int b = 0; b < supersample; ++b)
                    for (int a = 0; a < supersample; ++a) {
                        const DiskPoint p = disk_subpixel_point(static_cast<int>(r), c, b, a, n, supersample);
                        if (inside_unit_disk(p)) sum += value(p);
                    }
                pixel_sums[r * n + c] = sum;
            }
    });
    store_subpixel_means(image, layer, pixel_sums, supersample);
}

void copy_first_layer_to_all(LobeImage& image) {
    const std::size_t pixels = std::size_t(image.resolution) * image.resolution;
    for (std::size_t layer = 1; layer < image.layers(); ++layer)
        std::copy_n(image.values.begin(), pixels, image.values.begin() + layer * pixels);
}

}  // namespace glintscope
