#include "methods/discrete/spherical_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace glintscope {

std::array<SphericalTriangle, 4> hemisphere_quadrants() {
    const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    const Vec3 mx{-1, 0, 0}, my{0, -1, 0};
    return {SphericalTriangle{{x, y, z}}, SphericalTriangle{{y, mx, z}}, SphericalTriangle{{mx, my, z}},
            SphericalTriangle{{my, x, z}}};
}

std::array<SphericalTriangle, 4> split(const SphericalTriangle& t) {
    const Vec3 m01 = normalize(t.v[0] + t.v[1]);
    const Vec3 m12 = normalize(t.v[1] + t.v[2]);
    const Vec3 m20 = normalize(t.v[2] + t.v[0]);
    return {SphericalTriangle{{t.v[0], m01, m20}}, SphericalTriangle{{m01, t.v[1], m12}},
            SphericalTriangle{{m20, m12, t.v[2]}}, SphericalTriangle{{m01, m12, m20}}};
}

double solid_angle(const SphericalTriangle& t) {
    const double triple = std::abs(dot(t.v[0], cross(t.v[1], t.v[2])));
    const double denominator = 1.0 + dot(t.v[0], t.v[1]) + dot(t.v[1], t.v[2]) + dot(t.v[2], t.v[0]);
    return 2.0 * std::atan2(triple, denominator);
}

Vec3 centre(const SphericalTriangle& t) { return normalize(t.v[0] + t.v[1] + t.v[2]); }

bool contains(const SphericalTriangle& t, Vec3 m) {
    return dot(cross(t.v[0], t.v[1]), m) >= 0.0 && dot(cross(t.v[1], t.v[2]), m) >= 0.0 &&
           dot(cross(t.v[2], t.v[0]), m) >= 0.0;
}

SphericalConic spherical_conic(Vec3 omega_i, Vec3 omega_o, double gamma) {
    SphericalConic conic;
    const double diagonal = 0.5 * (std::cos(gamma) + dot(omega_i, omega_o));  // Jakob 2014 eq. 8
    const double a[3] = {omega_i.x, omega_i.y, omega_i.z};
    const double b[3] = {omega_o.x, omega_o.y, omega_o.z};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) conic.c[r][c] = (r == c ? diagonal : 0.0) - 0.5 * (a[r] * b[c] + b[r] * a[c]);
    conic.axis = normalize(omega_i + omega_o);
    conic.facing = omega_i;
    conic.elliptic = dot(omega_i, omega_o) + std::cos(gamma) > 0.0;  // λ1 > 0, Jakob 2014 eq. 9
    return conic;
}

double quadratic_form(const SphericalConic& conic, Vec3 m) {
    const double v[3] = {m.x, m.y, m.z};
    double sum = 0.0;
    for (int r = 0; r < 3; ++r) sum += v[r] * (conic.c[r][0] * v[0] + conic.c[r][1] * v[1] + conic.c[r][2] * v[2]);
    return sum;
}

double bilinear_form(const SphericalConic& conic, Vec3 a, Vec3 b) {
    const double u[3] = {a.x, a.y, a.z};
    const double v[3] = {b.x, b.y, b.z};
    double sum = 0.0;
    for (int r = 0; r < 3; ++r) sum += u[r] * (conic.c[r][0] * v[0] + conic.c[r][1] * v[1] + conic.c[r][2] * v[2]);
    return sum;
}

// −m reflects like m; only normals facing the light belong to the set.
bool contains(const SphericalConic& conic, Vec3 m) {
    return quadratic_form(conic, m) <= 0.0 && dot(m, conic.facing) > 0.0;
}

namespace {

// Whether the arc from a to b crosses the conic's boundary: the chord p(t) = (a + b) + t(a − b),
// t ∈ [−1, 1], meets the cone where dᵀCd t² + 2dᵀCc t + cᵀCc = 0 (Jakob 2014 §3.3), from
// aᵀCa, bᵀCb and aᵀCb.
bool arc_crosses(const SphericalConic& conic, Vec3 a, Vec3 b, double aa, double bb, double ab) {
    const Vec3 c = a + b;
    const Vec3 d = a - b;
    const double qa = aa - 2.0 * ab + bb;
    const double qb = aa - bb;
    const double qc = aa + 2.0 * ab + bb;
    const auto on_facing_nappe = [&](double t) { return t >= -1.0 && t <= 1.0 && dot(c + t * d, conic.facing) > 0.0; };
    if (std::abs(qa) < 1e-300) return qb != 0.0 && on_facing_nappe(-qc / (2.0 * qb));
    const double discriminant = qb * qb - qa * qc;
    if (discriminant < 0.0) return false;
    // The stable pair of roots (no cancellation between −qb and the square root).
    const double q = -(qb + std::copysign(std::sqrt(discriminant), qb));
    if (on_facing_nappe(q / qa)) return true;
    return q != 0.0 && on_facing_nappe(qc / q);
}

struct Point2d {
    double x, y;
};

double cross2(Point2d a, Point2d b) { return a.x * b.y - a.y * b.x; }

// The unit disk's part of the triangle (0, a, b), signed: its area and first moments ∫x, ∫y.
struct Moments {
    double area = 0.0, x = 0.0, y = 0.0;
};

// Straight pieces of the edge inside the disk add their triangle with the origin (moments: area
// times the centroid (p + q)/3); pieces outside add their circular sector (∫x = (sin β − sin α)/3,
// ∫y = (cos α − cos β)/3 for a unit sector from angle α to β).
Moments disk_wedge(Point2d a, Point2d b) {
    Moments moments;
    const Point2d d{b.x - a.x, b.y - a.y};
    const double qa = d.x * d.x + d.y * d.y;
    if (qa == 0.0) return moments;
    const double qb = a.x * d.x + a.y * d.y;
    const double qc = a.x * a.x + a.y * a.y - 1.0;
    double cuts[4] = {0.0, 0.0, 0.0, 1.0};
    int count = 1;
    const double discriminant = qb * qb - qa * qc;
    if (discriminant > 0.0) {
        const double root = std::sqrt(discriminant);
        for (double t : {(-qb - root) / qa, (-qb + root) / qa})
            if (t > 0.0 && t < 1.0) cuts[count++] = t;
    }
    cuts[count++] = 1.0;
    for (int k = 0; k + 1 < count; ++k) {
        const Point2d p{a.x + cuts[k] * d.x, a.y + cuts[k] * d.y};
        const Point2d q{a.x + cuts[k + 1] * d.x, a.y + cuts[k + 1] * d.y};
        const double tm = 0.5 * (cuts[k] + cuts[k + 1]);
        const Point2d mid{a.x + tm * d.x, a.y + tm * d.y};
        if (mid.x * mid.x + mid.y * mid.y <= 1.0) {
            const double area = 0.5 * cross2(p, q);
            moments.area += area;
            moments.x += area * (p.x + q.x) / 3.0;
            moments.y += area * (p.y + q.y) / 3.0;
        } else {
            // The sector between the rays through p and q: sin and cos of its bounding angles are
            // the rays' unit vectors.
            const double lp = std::hypot(p.x, p.y), lq = std::hypot(q.x, q.y);
            moments.area += 0.5 * std::atan2(cross2(p, q), p.x * q.x + p.y * q.y);
            moments.x += (q.y / lq - p.y / lp) / 3.0;
            moments.y += (p.x / lp - q.x / lq) / 3.0;
        }
    }
    return moments;
}

}  // namespace

Overlap overlap(const SphericalConic& conic, const SphericalTriangle& t) {
    double form[3], cross_form[3];
    for (int k = 0; k < 3; ++k) {
        form[k] = quadratic_form(conic, t.v[k]);
        cross_form[k] = bilinear_form(conic, t.v[k], t.v[(k + 1) % 3]);
    }
    for (int k = 0; k < 3; ++k)
        if (arc_crosses(conic, t.v[k], t.v[(k + 1) % 3], form[k], form[(k + 1) % 3], cross_form[k])) return Overlap::partial;
    if (form[0] <= 0.0 && dot(t.v[0], conic.facing) > 0.0) return Overlap::inside;
    return contains(t, conic.axis) ? Overlap::partial : Overlap::disjoint;
}

double inside_fraction(const SphericalConic& conic, const SphericalTriangle& t, const std::array<double, 3>& weights) {
    const Vec3 origin = (1.0 / 3.0) * (t.v[0] + t.v[1] + t.v[2]);
    const Vec3 e1 = normalize(t.v[1] - t.v[0]);
    const Vec3 e2 = normalize(cross(cross(t.v[1] - t.v[0], t.v[2] - t.v[0]), e1));
    // Q(x) = xᵀAx + 2bᵀx + q0 on the plane point origin + x1 e1 + x2 e2.
    const double a11 = quadratic_form(conic, e1), a22 = quadratic_form(conic, e2), a12 = bilinear_form(conic, e1, e2);
    const double b1 = bilinear_form(conic, e1, origin), b2 = bilinear_form(conic, e2, origin);
    const double q0 = quadratic_form(conic, origin);
    const double det = a11 * a22 - a12 * a12;
    if (!(a11 > 0.0 && det > 0.0)) return -1.0;
    const double cx = -(a22 * b1 - a12 * b2) / det;
    const double cy = -(a11 * b2 - a12 * b1) / det;
    const double k = q0 + b1 * cx + b2 * cy;
    if (!(k < 0.0) || dot(origin + cx * e1 + cy * e2, conic.facing) <= 0.0) return 0.0;
    // y = Lᵀ(x − c)/√(−k) with A = L Lᵀ maps the ellipse to the unit disk; areas scale alike.
    const double l11 = std::sqrt(a11), l21 = a12 / l11, l22 = std::sqrt(det) / l11;
    const double scale = 1.0 / std::sqrt(-k);
    Point2d y[3];
    for (int v = 0; v < 3; ++v) {
        const double x1 = dot(t.v[v] - origin, e1) - cx, x2 = dot(t.v[v] - origin, e2) - cy;
        y[v] = {scale * (l11 * x1 + l21 * x2), scale * l22 * x2};
    }
    const Point2d e{y[1].x - y[0].x, y[1].y - y[0].y}, f{y[2].x - y[0].x, y[2].y - y[0].y};
    const double triangle_area = 0.5 * cross2(e, f);
    if (triangle_area == 0.0) return -1.0;
    Moments inside;
    for (int v = 0; v < 3; ++v) {
        const Moments wedge = disk_wedge(y[v], y[(v + 1) % 3]);
        inside.area += wedge.area;
        inside.x += wedge.x;
        inside.y += wedge.y;
    }
    // The weight w(y) = w0 + g·(y − y0), linear through the vertex weights: ∫ over the inside part
    // against ∫ over the triangle (its area times the mean vertex weight).
    const double dw1 = weights[1] - weights[0], dw2 = weights[2] - weights[0];
    const double twice = 2.0 * triangle_area;
    const double gx = (dw1 * f.y - dw2 * e.y) / twice, gy = (dw2 * e.x - dw1 * f.x) / twice;
    const double inside_weight = (weights[0] - gx * y[0].x - gy * y[0].y) * inside.area + gx * inside.x + gy * inside.y;
    const double total_weight = triangle_area * (weights[0] + weights[1] + weights[2]) / 3.0;
    // No weight anywhere in the triangle: its share does not matter, the area's is as good as any.
    if (!(total_weight > 0.0)) return std::clamp(inside.area / triangle_area, 0.0, 1.0);
    return std::clamp(inside_weight / total_weight, 0.0, 1.0);
}

}  // namespace glintscope
