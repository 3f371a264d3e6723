// facet math: determinants and inverses (general and affine) of Mat3 and Mat4.
#include <cmath>

#include "facet/math/mat.hpp"

namespace facet {
namespace {

// A matrix is treated as singular when |det| is below this fraction of the product of its column
// lengths (Hadamard's bound on |det|): a scale-free test, so tiny but well-shaped matrices still invert.
constexpr double k_singular_ratio = 1e-7;

bool all_finite(const float* v, int n) {
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

}  // namespace

float determinant(const Mat3& m) {
    return m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)) -
           m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0)) +
           m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
}

std::optional<Mat3> inverse(const Mat3& m) {
    if (!all_finite(&m.col[0].x, 9)) return std::nullopt;
    double a[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) a[r][c] = m(r, c);
    double cof[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            int r0 = (r + 1) % 3, r1 = (r + 2) % 3, c0 = (c + 1) % 3, c1 = (c + 2) % 3;
            cof[r][c] = a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0];
        }
    double det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
    double bound = 1;
    for (int c = 0; c < 3; ++c) bound *= std::sqrt(a[0][c] * a[0][c] + a[1][c] * a[1][c] + a[2][c] * a[2][c]);
    if (!(std::fabs(det) > k_singular_ratio * bound)) return std::nullopt;
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = static_cast<float>(cof[j][i] / det);
    return r;
}

namespace {

// The 4x4 cofactor expansion in double: returns the adjugate (transposed cofactors) and the determinant.
double adjugate4(const Mat4& m, double adj[4][4]) {
    double a[16];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) a[r * 4 + c] = m(r, c);
    // 2x2 minors of the top two rows (s) and the bottom two rows (t).
    double s0 = a[0] * a[5] - a[4] * a[1], s1 = a[0] * a[6] - a[4] * a[2], s2 = a[0] * a[7] - a[4] * a[3];
    double s3 = a[1] * a[6] - a[5] * a[2], s4 = a[1] * a[7] - a[5] * a[3], s5 = a[2] * a[7] - a[6] * a[3];
    double c5 = a[10] * a[15] - a[14] * a[11], c4 = a[9] * a[15] - a[13] * a[11], c3 = a[9] * a[14] - a[13] * a[10];
    double c2 = a[8] * a[15] - a[12] * a[11], c1 = a[8] * a[14] - a[12] * a[10], c0 = a[8] * a[13] - a[12] * a[9];
    double det = s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
    adj[0][0] = a[5] * c5 - a[6] * c4 + a[7] * c3;
    adj[0][1] = -a[1] * c5 + a[2] * c4 - a[3] * c3;
    adj[0][2] = a[13] * s5 - a[14] * s4 + a[15] * s3;
    adj[0][3] = -a[9] * s5 + a[10] * s4 - a[11] * s3;
    adj[1][0] = -a[4] * c5 + a[6] * c2 - a[7] * c1;
    adj[1][1] = a[0] * c5 - a[2] * c2 + a[3] * c1;
    adj[1][2] = -a[12] * s5 + a[14] * s2 - a[15] * s1;
    adj[1][3] = a[8] * s5 - a[10] * s2 + a[11] * s1;
    adj[2][0] = a[4] * c4 - a[5] * c2 + a[7] * c0;
    adj[2][1] = -a[0] * c4 + a[1] * c2 - a[3] * c0;
    adj[2][2] = a[12] * s4 - a[13] * s2 + a[15] * s0;
    adj[2][3] = -a[8] * s4 + a[9] * s2 - a[11] * s0;
    adj[3][0] = -a[4] * c3 + a[5] * c1 - a[6] * c0;
    adj[3][1] = a[0] * c3 - a[1] * c1 + a[2] * c0;
    adj[3][2] = -a[12] * s3 + a[13] * s1 - a[14] * s0;
    adj[3][3] = a[8] * s3 - a[9] * s1 + a[10] * s0;
    return det;
}

double column_length_product(const Mat4& m) {
    // In double: a float dot product overflows for entries above ~1.8e19, which made huge but
    // well-shaped matrices look singular.
    double bound = 1;
    for (int c = 0; c < 4; ++c) {
        double s = 0;
        for (int r = 0; r < 4; ++r) s += static_cast<double>(m(r, c)) * m(r, c);
        bound *= std::sqrt(s);
    }
    return bound;
}

}  // namespace

float determinant(const Mat4& m) {
    double adj[4][4];
    return static_cast<float>(adjugate4(m, adj));
}

std::optional<Mat4> inverse(const Mat4& m) {
    if (!all_finite(&m.col[0].x, 16)) return std::nullopt;
    double adj[4][4];
    double det = adjugate4(m, adj);
    if (!(std::fabs(det) > k_singular_ratio * column_length_product(m))) return std::nullopt;
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r(i, j) = static_cast<float>(adj[i][j] / det);
    return r;
}

std::optional<Mat4> affine_inverse(const Mat4& m) {
    std::optional<Mat3> a = inverse(m.upper3x3());
    if (!a) return std::nullopt;
    Vec3 t = -(*a * m.col[3].xyz());
    if (!is_finite(t)) return std::nullopt;  // non-finite translation, as inverse() does
    Mat4 r;
    for (int c = 0; c < 3; ++c) r.col[c] = Vec4(a->col[c], 0);
    r.col[3] = Vec4(t, 1);
    return r;
}

Mat3 normal_matrix(const Mat4& model) {
    Mat3 m = model.upper3x3();
    std::optional<Mat3> inv = inverse(m);
    return inv ? transpose(*inv) : m;
}

}  // namespace facet
