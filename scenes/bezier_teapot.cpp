#include "scenes/bezier_teapot.h"

#include <algorithm>
#include <array>
#include <bit>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenes/teapot_data.h"

namespace trident {

namespace {

using teapot_data::kControlPoints;
using teapot_data::kPatches;

Vec3f control_point(std::uint16_t i) { return {kControlPoints[i][0], kControlPoints[i][1], kControlPoints[i][2]}; }

void check_segments(std::uint32_t segments) {
    if (segments < kMinTeapotSegments || segments > kMaxTeapotSegments)
        throw std::invalid_argument("bezier teapot: segments must be in [" + std::to_string(kMinTeapotSegments) + ", " +
                                    std::to_string(kMaxTeapotSegments) + "], got " + std::to_string(segments));
}

/// The four control point indices along one boundary of a patch (edge 0..3: first row, last
/// row, first column, last column).
std::array<std::uint16_t, 4> boundary(const std::array<std::uint16_t, 16>& patch, int edge) {
    std::array<std::uint16_t, 4> out{};
    for (int k = 0; k < 4; ++k) {
        switch (edge) {
            case 0:
                out[k] = patch[k];
                break;
            case 1:
                out[k] = patch[12 + k];
                break;
            case 2:
                out[k] = patch[4 * k];
                break;
            default:
                out[k] = patch[4 * k + 3];
                break;
        }
    }
    return out;
}

bool is_collapsed(const std::array<std::uint16_t, 4>& curve) {
    return std::all_of(curve.begin(), curve.end(),
                       [&](std::uint16_t i) { return control_point(i) == control_point(curve[0]); });
}

/// Bernstein weights scaled to integers: C(3, i) j^i (n - j)^(3 - i) = n^3 B_i(j / n), exact.
std::vector<std::array<double, 4>> bernstein_numerators(std::uint32_t n) {
    std::vector<std::array<double, 4>> w(n + 1);
    for (std::uint32_t j = 0; j <= n; ++j) {
        const double s = j, t = n - j;
        w[j] = {t * t * t, 3.0 * s * t * t, 3.0 * s * s * t, s * s * s};
    }
    return w;
}

/// One coordinate of a patch point as the sum of its 16 terms weight * control value. Each term
/// is exact in double (weights below 2^29 times 24-bit floats) and the sum runs in sorted order,
/// so the two patches meeting at a seam, which hold the same terms in another order (or the
/// reverse parameter direction), get bit-identical points and the seam welds.
float patch_coordinate(std::array<double, 16> terms, double denominator) {
    std::sort(terms.begin(), terms.end());
    double sum = 0.0;
    for (double t : terms) sum += t;
    return float(sum / denominator);
}

/// Welds identical positions into one vertex (first occurrence keeps its place).
class VertexWelder {
public:
    explicit VertexWelder(Mesh& mesh) : mesh_(mesh) {}
    std::uint32_t add(Vec3f p) {
        p = p + Vec3f(0.0f);  // -0 and +0 are one position
        const Key key{std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y),
                      std::bit_cast<std::uint32_t>(p.z)};
        const auto [it, inserted] = index_.try_emplace(key, std::uint32_t(mesh_.vertex_count()));
        if (inserted) mesh_.add_vertex(p);
        return it->second;
    }

private:
    using Key = std::array<std::uint32_t, 3>;
    Mesh& mesh_;
    std::map<Key, std::uint32_t> index_;
};

}  // namespace

std::size_t bezier_teapot_triangle_count(std::uint32_t segments) {
    check_segments(segments);
    std::size_t collapsed_edges = 0;
    for (const auto& patch : kPatches)
        for (int edge = 0; edge < 4; ++edge) collapsed_edges += is_collapsed(boundary(patch, edge)) ? 1 : 0;
    return kPatches.size() * 2 * segments * segments - collapsed_edges * segments;
}

Mesh make_bezier_teapot(std::uint32_t segments) {
    check_segments(segments);
    const std::uint32_t n = segments;
    const auto weights = bernstein_numerators(n);
    const double denominator = double(n) * n * n * n * n * n;  // (n^3)^2 from the two weights
    Mesh mesh;
    VertexWelder welder(mesh);
    std::vector<std::uint32_t> grid((n + 1) * (n + 1));
    for (const auto& patch : kPatches) {
        for (std::uint32_t a = 0; a <= n; ++a)
            for (std::uint32_t b = 0; b <= n; ++b) {
                std::array<std::array<double, 16>, 3> terms{};
                for (int r = 0; r < 4; ++r)
                    for (int c = 0; c < 4; ++c) {
                        const double w = weights[a][r] * weights[b][c];
                        const Vec3f p = control_point(patch[4 * r + c]);
                        terms[0][4 * r + c] = w * p.x;
                        terms[1][4 * r + c] = w * p.y;
                        terms[2][4 * r + c] = w * p.z;
                    }
                const float x = patch_coordinate(terms[0], denominator), y = patch_coordinate(terms[1], denominator),
                            z = patch_coordinate(terms[2], denominator);
                grid[a * (n + 1) + b] = welder.add({x, z, -y});  // z up -> y up, a rotation: winding kept
            }
        // Newell's patches have du x dv pointing inwards, so each quad is wound v00, v11, v10.
        auto emit = [&](std::uint32_t i0, std::uint32_t i1, std::uint32_t i2) {
            if (i0 != i1 && i1 != i2 && i2 != i0) mesh.add_triangle(i0, i1, i2);
        };
        for (std::uint32_t a = 0; a < n; ++a)
            for (std::uint32_t b = 0; b < n; ++b) {
                const std::uint32_t v00 = grid[a * (n + 1) + b], v01 = grid[a * (n + 1) + b + 1];
                const std::uint32_t v10 = grid[(a + 1) * (n + 1) + b], v11 = grid[(a + 1) * (n + 1) + b + 1];
                emit(v00, v11, v10);
                emit(v00, v01, v11);
            }
    }
    return mesh;
}

}  // namespace trident
