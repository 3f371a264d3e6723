// Mat3 / Mat4: layout, products, transpose, determinant, general and affine inverse, normal matrix,
// against GLM (float, and double where an exact reference is needed) and hand-derived values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "facet/math/mat.hpp"
#include "facet/math/transform.hpp"
#include "support/glm_compare.hpp"

namespace {

using namespace facet;
using facet_test::all_finite;
using facet_test::float_near;
using facet_test::from_glm;
using facet_test::mat_near;
using facet_test::Rng;
using facet_test::to_glm;
using facet_test::vec_near;

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();
constexpr float k_inf = std::numeric_limits<float>::infinity();

// ---- helpers ---------------------------------------------------------------------------------------

double frobenius(const glm::dmat4& m) {
    double s = 0;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) s += m[c][r] * m[c][r];
    return std::sqrt(s);
}
double frobenius(const glm::dmat3& m) {
    double s = 0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) s += m[c][r] * m[c][r];
    return std::sqrt(s);
}

// Hadamard's bound on |det|: the product of the column lengths. The natural scale for determinant
// errors, since the determinant may cancel to a value much smaller than its terms.
double hadamard(const Mat4& m) {
    double b = 1;
    for (const Vec4& c : m.col) b *= std::sqrt(double(c.x) * c.x + double(c.y) * c.y + double(c.z) * c.z + double(c.w) * c.w);
    return b;
}
double hadamard(const Mat3& m) {
    double b = 1;
    for (const Vec3& c : m.col) b *= std::sqrt(double(c.x) * c.x + double(c.y) * c.y + double(c.z) * c.z);
    return b;
}

// A random matrix with entries in [-1, 1] whose Frobenius condition number ||M|| ||M^-1|| (computed
// in double) is at most max_cond: "well conditioned", so float results can be held to ~1e-5.
Mat4 random_well_conditioned4(Rng& rng, double max_cond) {
    for (;;) {
        Mat4 m = rng.mat4(-1, 1);
        glm::dmat4 d(to_glm(m));
        if (std::fabs(glm::determinant(d)) < 1e-3) continue;
        if (frobenius(d) * frobenius(glm::inverse(d)) <= max_cond) return m;
    }
}
Mat3 random_well_conditioned3(Rng& rng, double max_cond) {
    for (;;) {
        Mat3 m = rng.mat3(-1, 1);
        glm::dmat3 d(to_glm(m));
        if (std::fabs(glm::determinant(d)) < 1e-3) continue;
        if (frobenius(d) * frobenius(glm::inverse(d)) <= max_cond) return m;
    }
}

// A random affine matrix T * R * S: translation up to 50, rotation about a random axis, scale factors
// of either sign with magnitudes in [0.2, 5].
Mat4 random_affine(Rng& rng) {
    Vec3 s{rng.uniform(0.2f, 5) * rng.sign(), rng.uniform(0.2f, 5) * rng.sign(), rng.uniform(0.2f, 5) * rng.sign()};
    return translate(rng.vec3(-50, 50)) * rotate(rng.unit3(), rng.uniform(-k_pi, k_pi)) * scale(s);
}

// ---- layout ----------------------------------------------------------------------------------------

TEST(MatLayout, ColumnMajorStorageMatchesGlmMemoryLayout) {
    static_assert(sizeof(Mat4) == 16 * sizeof(float));
    static_assert(sizeof(Mat3) == 9 * sizeof(float));
    Rng rng(201);
    Mat4 m = rng.mat4(-10, 10);
    // Copying the bytes into a glm::mat4 must give the same matrix element by element:
    // facet m(row, col) == glm g[col][row].
    glm::mat4 g;
    std::memcpy(glm::value_ptr(g), &m, sizeof m);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) EXPECT_EQ(m(r, c), g[c][r]) << r << "," << c;
    Mat3 m3 = rng.mat3(-10, 10);
    glm::mat3 g3;
    std::memcpy(glm::value_ptr(g3), &m3, sizeof m3);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(m3(r, c), g3[c][r]) << r << "," << c;
}

TEST(MatLayout, AccessorsIndexRowThenColumn) {
    // from_rows takes the matrix as written on paper: row 1 is 1 2 3 4.
    const float rows[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    Mat4 m = Mat4::from_rows(rows);
    EXPECT_EQ(m(0, 1), 2.0f);
    EXPECT_EQ(m(1, 0), 5.0f);
    EXPECT_EQ(m(3, 2), 15.0f);
    EXPECT_EQ(m.col[0], (Vec4{1, 5, 9, 13}));
    EXPECT_EQ(m.col[3], (Vec4{4, 8, 12, 16}));
    // glm::make_mat4 reads column-major, so it reads the same 16 numbers as the transpose.
    EXPECT_EQ(m, from_glm(glm::transpose(glm::make_mat4(rows))));
    Mat3 u = m.upper3x3();
    EXPECT_EQ(u(0, 0), 1.0f);
    EXPECT_EQ(u(0, 2), 3.0f);
    EXPECT_EQ(u(2, 0), 9.0f);
    EXPECT_EQ(u(2, 2), 11.0f);
    EXPECT_TRUE(mat_near(u, glm::mat3(to_glm(m)), 0));
}

TEST(MatLayout, IdentityAndZero) {
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            EXPECT_EQ(Mat4::identity()(r, c), r == c ? 1.0f : 0.0f);
            EXPECT_EQ(Mat4{}(r, c), r == c ? 1.0f : 0.0f);
            EXPECT_EQ(Mat4::zero()(r, c), 0.0f);
        }
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(Mat3::identity()(r, c), r == c ? 1.0f : 0.0f);
}

// ---- products --------------------------------------------------------------------------------------

TEST(MatProduct, Mat4TimesMat4MatchesGlm) {
    Rng rng(202);
    for (int it = 0; it < 2000; ++it) {
        Mat4 a = rng.mat4(-10, 10), b = rng.mat4(-10, 10);
        EXPECT_TRUE(mat_near(a * b, to_glm(a) * to_glm(b)));
    }
}

TEST(MatProduct, Mat3TimesMat3MatchesGlm) {
    Rng rng(203);
    for (int it = 0; it < 2000; ++it) {
        Mat3 a = rng.mat3(-10, 10), b = rng.mat3(-10, 10);
        EXPECT_TRUE(mat_near(a * b, to_glm(a) * to_glm(b)));
    }
}

TEST(MatProduct, MatrixTimesVectorMatchesGlm) {
    Rng rng(204);
    for (int it = 0; it < 2000; ++it) {
        Mat4 m = rng.mat4(-10, 10);
        Vec4 v = rng.vec4(-10, 10);
        EXPECT_TRUE(vec_near(m * v, to_glm(m) * to_glm(v)));
        Mat3 m3 = rng.mat3(-10, 10);
        Vec3 v3 = rng.vec3(-10, 10);
        EXPECT_TRUE(vec_near(m3 * v3, to_glm(m3) * to_glm(v3)));
    }
}

TEST(MatProduct, HandDerivedColumnVectorConvention) {
    // Rows (1 2 3 4 / 5 6 7 8 / ...) times (1, 0, 0, 1): column 0 plus column 3.
    const float rows[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    Mat4 m = Mat4::from_rows(rows);
    EXPECT_EQ(m * Vec4(1, 0, 0, 1), (Vec4{5, 13, 21, 29}));
    // (1 2; 3 4)-style check of A*B order: translate then scale differs from scale then translate.
    Mat4 ts = translate({1, 2, 3}) * scale(2.0f);   // scale first, then translate
    Mat4 st = scale(2.0f) * translate({1, 2, 3});   // translate first, then scale
    EXPECT_EQ(transform_point(ts, {1, 1, 1}), (Vec3{3, 4, 5}));
    EXPECT_EQ(transform_point(st, {1, 1, 1}), (Vec3{4, 6, 8}));
    // Identity is neutral on both sides.
    Rng rng(205);
    Mat4 r = rng.mat4(-5, 5);
    EXPECT_EQ(r * Mat4::identity(), r);
    EXPECT_EQ(Mat4::identity() * r, r);
}

TEST(MatProduct, PointsTranslateAndDirectionsDoNot) {
    Mat4 m = translate({10, 20, 30}) * scale(Vec3{2, 3, 4});
    EXPECT_EQ(transform_point(m, {1, 1, 1}), (Vec3{12, 23, 34}));
    EXPECT_EQ(transform_direction(m, {1, 1, 1}), (Vec3{2, 3, 4}));
}

// ---- transpose and determinant -----------------------------------------------------------------------

TEST(MatTranspose, MatchesGlmAndIsAnInvolution) {
    Rng rng(206);
    for (int it = 0; it < 200; ++it) {
        Mat4 m = rng.mat4(-10, 10);
        EXPECT_EQ(transpose(m), from_glm(glm::transpose(to_glm(m))));
        EXPECT_EQ(transpose(transpose(m)), m);
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) EXPECT_EQ(transpose(m)(r, c), m(c, r));
        Mat3 m3 = rng.mat3(-10, 10);
        EXPECT_TRUE(mat_near(transpose(m3), glm::transpose(to_glm(m3)), 0));
        // (AB)^T = B^T A^T
        Mat4 a = rng.mat4(-3, 3), b = rng.mat4(-3, 3);
        EXPECT_TRUE(mat_near(transpose(a * b), transpose(b) * transpose(a)));
    }
}

TEST(MatDeterminant, MatchesGlm) {
    Rng rng(207);
    for (int it = 0; it < 2000; ++it) {
        Mat4 m = rng.mat4(-10, 10);
        // facet computes in double: hold it to the exact (double) determinant of the float matrix.
        EXPECT_TRUE(float_near(determinant(m), glm::determinant(glm::dmat4(to_glm(m))), 1e-6, hadamard(m)));
        EXPECT_TRUE(float_near(determinant(m), glm::determinant(to_glm(m)), 1e-5, hadamard(m)));
        Mat3 m3 = rng.mat3(-10, 10);
        EXPECT_TRUE(float_near(determinant(m3), glm::determinant(glm::dmat3(to_glm(m3))), 1e-6, hadamard(m3)));
        EXPECT_TRUE(float_near(determinant(m3), glm::determinant(to_glm(m3)), 1e-5, hadamard(m3)));
    }
}

TEST(MatDeterminant, HandDerivedValues) {
    EXPECT_FLOAT_EQ(determinant(Mat4::identity()), 1.0f);
    EXPECT_FLOAT_EQ(determinant(Mat4::zero()), 0.0f);
    EXPECT_FLOAT_EQ(determinant(scale(Vec3{2, 3, 4})), 24.0f);
    EXPECT_FLOAT_EQ(determinant(scale(Vec3{2, 3, 4}).upper3x3()), 24.0f);
    EXPECT_FLOAT_EQ(determinant(scale(Vec3{-1, 1, 1})), -1.0f);
    // Translation does not change volume; rotations keep it at 1.
    EXPECT_FLOAT_EQ(determinant(translate({7, -8, 9})), 1.0f);
    EXPECT_NEAR(determinant(rotate({1, 2, 3}, 0.7f)), 1.0f, 1e-6f);
    // Swapping two rows (x <-> y) flips the sign.
    const float swap_xy[16] = {0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    EXPECT_FLOAT_EQ(determinant(Mat4::from_rows(swap_xy)), -1.0f);
    // An upper triangular matrix: the product of its diagonal.
    const float tri[16] = {2, 5, 7, 1, 0, 3, 8, 2, 0, 0, -4, 3, 0, 0, 0, 0.5f};
    EXPECT_FLOAT_EQ(determinant(Mat4::from_rows(tri)), 2 * 3 * -4 * 0.5f);
    EXPECT_FLOAT_EQ(determinant(transpose(Mat4::from_rows(tri))), 2 * 3 * -4 * 0.5f);
}

TEST(MatDeterminant, IsMultiplicative) {
    Rng rng(208);
    for (int it = 0; it < 500; ++it) {
        Mat4 a = rng.mat4(-2, 2), b = rng.mat4(-2, 2);
        double scale_ab = hadamard(a) * hadamard(b);
        EXPECT_TRUE(float_near(determinant(a * b), double(determinant(a)) * determinant(b), 1e-5, scale_ab));
    }
}

// ---- general inverse ---------------------------------------------------------------------------------

TEST(MatInverse, Mat4MatchesGlmForWellConditionedMatrices) {
    Rng rng(209);
    for (int it = 0; it < 2000; ++it) {
        Mat4 m = random_well_conditioned4(rng, 20);
        std::optional<Mat4> inv = inverse(m);
        ASSERT_TRUE(inv.has_value()) << ::testing::PrintToString(m);
        // Against the exact inverse of the float matrix (double GLM): facet inverts in double, so
        // only the final rounding to float remains.
        EXPECT_TRUE(mat_near(*inv, from_glm(glm::mat4(glm::inverse(glm::dmat4(to_glm(m))))), 1e-6f));
        // Against GLM's float inverse, which carries its own error of about cond * epsilon.
        EXPECT_TRUE(mat_near(*inv, glm::inverse(to_glm(m))));
    }
}

TEST(MatInverse, Mat4RoundTripGivesIdentity) {
    Rng rng(210);
    for (int it = 0; it < 2000; ++it) {
        Mat4 m = random_well_conditioned4(rng, 20);
        std::optional<Mat4> inv = inverse(m);
        ASSERT_TRUE(inv.has_value());
        EXPECT_TRUE(mat_near(m * *inv, Mat4::identity()));
        EXPECT_TRUE(mat_near(*inv * m, Mat4::identity()));
    }
}

TEST(MatInverse, Mat3MatchesGlmAndRoundTrips) {
    Rng rng(211);
    for (int it = 0; it < 2000; ++it) {
        Mat3 m = random_well_conditioned3(rng, 15);
        std::optional<Mat3> inv = inverse(m);
        ASSERT_TRUE(inv.has_value());
        EXPECT_TRUE(mat_near(*inv, from_glm(glm::mat3(glm::inverse(glm::dmat3(to_glm(m))))), 1e-6f));
        EXPECT_TRUE(mat_near(*inv, glm::inverse(to_glm(m))));
        EXPECT_TRUE(mat_near(m * *inv, Mat3::identity()));
        EXPECT_TRUE(mat_near(*inv * m, Mat3::identity()));
    }
}

TEST(MatInverse, HandDerivedInverses) {
    std::optional<Mat4> s = inverse(scale(Vec3{2, -4, 0.5f}));
    ASSERT_TRUE(s);
    EXPECT_EQ(*s, scale(Vec3{0.5f, -0.25f, 2}));
    std::optional<Mat4> t = inverse(translate({1, -2, 3}));
    ASSERT_TRUE(t);
    EXPECT_EQ(*t, translate({-1, 2, -3}));
    // A rotation's inverse is its transpose.
    Mat4 r = rotate({1, -2, 0.5f}, 1.1f);
    std::optional<Mat4> ri = inverse(r);
    ASSERT_TRUE(ri);
    EXPECT_TRUE(mat_near(*ri, transpose(r)));
    EXPECT_TRUE(mat_near(*ri, rotate({1, -2, 0.5f}, -1.1f)));
}

// The singularity test is relative to the size of the entries, so uniformly tiny or huge matrices
// that are perfectly shaped still invert.
TEST(MatInverse, IsScaleFree) {
    for (float k : {1e-12f, 1e-6f, 1e6f, 1e12f, 1e20f, 1e30f}) {
        Mat4 m = Mat4::identity();
        for (auto& c : m.col) c = c * k;  // k * I, w included
        std::optional<Mat4> inv = inverse(m);
        ASSERT_TRUE(inv.has_value()) << "k = " << k;
        Mat4 expected = Mat4::identity();
        for (auto& c : expected.col) c = c * (1 / k);
        EXPECT_TRUE(mat_near(*inv, expected, 1e-6f)) << "k = " << k;
        // A well-conditioned random matrix times k.
        Rng rng(212);
        Mat4 r = random_well_conditioned4(rng, 20), rk = r;
        for (auto& c : rk.col) c = c * k;
        std::optional<Mat4> rinv = inverse(r), rkinv = inverse(rk);
        ASSERT_TRUE(rinv && rkinv) << "k = " << k;
        Mat4 scaled = *rinv;
        for (auto& c : scaled.col) c = c * (1 / k);
        EXPECT_TRUE(mat_near(*rkinv, scaled)) << "k = " << k;

        Mat3 m3 = Mat3::identity();
        for (auto& c : m3.col) c = c * k;
        std::optional<Mat3> inv3 = inverse(m3);
        ASSERT_TRUE(inv3.has_value()) << "k = " << k;
        EXPECT_TRUE(float_near(inv3->col[1].y, 1 / k, 1e-6)) << "k = " << k;
        // The affine inverse of a uniformly scaled affine matrix.
        std::optional<Mat4> a = affine_inverse(translate({1, 2, 3}) * scale(k));
        ASSERT_TRUE(a.has_value()) << "k = " << k;
        EXPECT_TRUE(mat_near(*a, scale(1 / k) * translate({-1, -2, -3}), 1e-6f)) << "k = " << k;
    }
}

Mat4 with_column(Mat4 m, int c, Vec4 v) {
    m.col[c] = v;
    return m;
}
Mat4 with_row(Mat4 m, int r, Vec4 v) {
    for (int c = 0; c < 4; ++c) m(r, c) = v[static_cast<std::size_t>(c)];
    return m;
}

TEST(MatInverse, SingularMatricesGiveNothing) {
    Rng rng(213);
    const Mat4 base = random_well_conditioned4(rng, 20);
    ASSERT_TRUE(inverse(base).has_value());
    EXPECT_FALSE(inverse(Mat4::zero()).has_value());
    EXPECT_FALSE(inverse(scale(0.0f)).has_value());
    EXPECT_FALSE(inverse(scale(Vec3{1, 0, 1})).has_value());
    EXPECT_FALSE(inverse(translate({1, 2, 3}) * scale(Vec3{2, 2, 0})).has_value());
    for (int i = 0; i < 4; ++i) {
        EXPECT_FALSE(inverse(with_row(base, i, Vec4{})).has_value()) << "zero row " << i;
        EXPECT_FALSE(inverse(with_column(base, i, Vec4{})).has_value()) << "zero column " << i;
        int j = (i + 1) % 4;
        EXPECT_FALSE(inverse(with_column(base, i, base.col[j])).has_value()) << "duplicate column " << i;
        EXPECT_FALSE(inverse(with_column(base, i, base.col[j] * -3.0f)).has_value()) << "parallel column " << i;
        Vec4 row_j{base(j, 0), base(j, 1), base(j, 2), base(j, 3)};
        EXPECT_FALSE(inverse(with_row(base, i, row_j)).has_value()) << "duplicate row " << i;
    }
    // The projection onto a plane: rank 3.
    const float flatten[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    EXPECT_FALSE(inverse(Mat4::from_rows(flatten)).has_value());
    // A perspective projection loses nothing, but its product with a flattening does.
    EXPECT_TRUE(inverse(perspective_rh_zo(1.0f, 1.5f, 0.1f, 100.0f)).has_value());
    EXPECT_FALSE(inverse(perspective_rh_zo(1.0f, 1.5f, 0.1f, 100.0f) * Mat4::from_rows(flatten)).has_value());
}

// Exactly singular random matrices: small integer entries, one column an integer combination of two
// others, so the dependency survives float storage exactly.
TEST(MatInverse, RandomRankDeficientMatricesGiveNothing) {
    Rng rng(214);
    for (int it = 0; it < 1000; ++it) {
        Mat4 m;
        for (auto& c : m.col)
            c = Vec4{float(rng.integer(-8, 8)), float(rng.integer(-8, 8)), float(rng.integer(-8, 8)),
                     float(rng.integer(-8, 8))};
        int dep = rng.integer(0, 3);
        int a = (dep + 1) % 4, b = (dep + 2) % 4;
        m.col[dep] = m.col[a] * float(rng.integer(-3, 3)) + m.col[b] * float(rng.integer(-3, 3));
        EXPECT_FALSE(inverse(m).has_value()) << ::testing::PrintToString(m);
        EXPECT_EQ(determinant(m), 0.0f);

        Mat3 m3;
        for (auto& c : m3.col) c = Vec3{float(rng.integer(-8, 8)), float(rng.integer(-8, 8)), float(rng.integer(-8, 8))};
        m3.col[dep % 3] = m3.col[(dep + 1) % 3] * float(rng.integer(-3, 3)) - m3.col[(dep + 2) % 3] * 2.0f;
        EXPECT_FALSE(inverse(m3).has_value()) << ::testing::PrintToString(m3);
    }
}

// The test is on the shape, not the size: two columns 1e-9 radians apart are numerically dependent
// (far below float precision), while a diagonal matrix with wildly different but exact scales is
// perfectly invertible.
TEST(MatInverse, NearlyParallelColumnsGiveNothingButColumnScalesDoNotMatter) {
    Mat4 m = Mat4::identity();
    m.col[1] = Vec4{1, 1e-9f, 0, 0};  // 1e-9 rad from column 0
    EXPECT_FALSE(inverse(m).has_value());
    Mat3 m3 = Mat3::identity();
    m3.col[2] = Vec3{0, 1, 1e-9f};  // 1e-9 rad from column 1
    EXPECT_FALSE(inverse(m3).has_value());
    EXPECT_FALSE(affine_inverse(m).has_value());

    m.col[1] = Vec4{1, 1e-3f, 0, 0};  // 1e-3 rad: well conditioned enough for float
    std::optional<Mat4> inv = inverse(m);
    ASSERT_TRUE(inv.has_value());
    EXPECT_TRUE(mat_near(m * *inv, Mat4::identity()));

    std::optional<Mat4> d = inverse(scale(Vec3{1e6f, 1e-12f, 1}));
    ASSERT_TRUE(d.has_value());
    EXPECT_TRUE(float_near((*d)(0, 0), 1e-6, 1e-6));
    EXPECT_TRUE(float_near((*d)(1, 1), 1e12, 1e-6));
    EXPECT_EQ((*d)(2, 2), 1.0f);
}

TEST(MatInverse, NonFiniteInputGivesNothing) {
    Rng rng(215);
    const Mat4 base = random_well_conditioned4(rng, 20);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            for (float bad : {k_nan, k_inf, -k_inf}) {
                Mat4 m = base;
                m(r, c) = bad;
                EXPECT_FALSE(inverse(m).has_value()) << r << "," << c << " = " << bad;
                if (r < 3 && c < 3) {
                    Mat3 m3 = Mat3::identity();
                    m3(r, c) = bad;
                    EXPECT_FALSE(inverse(m3).has_value()) << r << "," << c << " = " << bad;
                }
                if (r < 3) {
                    // The affine inverse reads the upper 3x4 block.
                    Mat4 a = translate({1, 2, 3});
                    a(r, c) = bad;
                    EXPECT_FALSE(affine_inverse(a).has_value()) << r << "," << c << " = " << bad;
                }
            }
}

// ---- affine inverse and normal matrix -----------------------------------------------------------------

TEST(MatAffineInverse, EqualsTheGeneralInverseForRandomAffineMatrices) {
    Rng rng(216);
    for (int it = 0; it < 2000; ++it) {
        Mat4 m = random_affine(rng);
        std::optional<Mat4> a = affine_inverse(m), g = inverse(m);
        ASSERT_TRUE(a && g);
        EXPECT_TRUE(mat_near(*a, *g));
        EXPECT_TRUE(mat_near(*a, glm::mat4(glm::inverse(glm::dmat4(to_glm(m))))));
        // The result is affine too: last row exactly (0, 0, 0, 1).
        EXPECT_EQ(a->col[0].w, 0.0f);
        EXPECT_EQ(a->col[1].w, 0.0f);
        EXPECT_EQ(a->col[2].w, 0.0f);
        EXPECT_EQ(a->col[3].w, 1.0f);
        // Undoes the transform of a point.
        Vec3 p = rng.vec3(-10, 10);
        EXPECT_TRUE(vec_near(transform_point(*a, transform_point(m, p)), p, 1e-4f));
    }
}

TEST(MatAffineInverse, SingularUpper3x3GivesNothing) {
    EXPECT_FALSE(affine_inverse(translate({1, 2, 3}) * scale(Vec3{1, 0, 1})).has_value());
    EXPECT_FALSE(affine_inverse(translate({1, 2, 3}) * scale(0.0f)).has_value());
    EXPECT_FALSE(affine_inverse(Mat4::zero()).has_value());
    Mat4 dup = rotate({0, 1, 0}, 0.3f);
    dup.col[2] = dup.col[0];
    EXPECT_FALSE(affine_inverse(dup).has_value());
    // Hand-derived: the inverse of T(t) * S(s) is S(1/s) * T(-t).
    std::optional<Mat4> a = affine_inverse(translate({4, 5, 6}) * scale(Vec3{2, 4, -8}));
    ASSERT_TRUE(a);
    EXPECT_TRUE(mat_near(*a, scale(Vec3{0.5f, 0.25f, -0.125f}) * translate({-4, -5, -6}), 1e-7f));
}

TEST(MatNormalMatrix, IsTransposeOfInverseOfUpper3x3) {
    Rng rng(217);
    for (int it = 0; it < 2000; ++it) {
        Mat4 m = random_affine(rng);
        Mat3 n = normal_matrix(m);
        EXPECT_TRUE(mat_near(n, glm::transpose(glm::inverse(glm::mat3(to_glm(m))))));
        // A normal stays perpendicular to the transformed surface: pick a plane with normal `nrm`
        // and a tangent `t` in it; M moves t, the normal matrix moves nrm, and they stay at 90 degrees.
        Vec3 nrm = rng.unit3();
        Vec3 t = normalize(cross(nrm, rng.unit3()));
        if (length(t) == 0) continue;
        Vec3 t2 = transform_direction(m, t);
        Vec3 n2 = n * nrm;
        EXPECT_TRUE(float_near(dot(normalize(n2), normalize(t2)), 0.0, 1e-5, 1.0));
    }
}

TEST(MatNormalMatrix, RotationsKeepTheirUpper3x3AndSingularFallsBack) {
    Mat4 r = rotate({1, 1, 0}, 0.8f);
    EXPECT_TRUE(mat_near(normal_matrix(r), r.upper3x3()));
    // Uniform scale 2 turns normals by S^-T = 0.5 I.
    Mat3 half = Mat3::identity();
    for (auto& c : half.col) c = c * 0.5f;
    EXPECT_TRUE(mat_near(normal_matrix(translate({1, 2, 3}) * scale(2.0f)), half, 0));
    // Non-uniform scale (1, 2, 4): normals scale by (1, 1/2, 1/4).
    Mat3 ns = normal_matrix(scale(Vec3{1, 2, 4}));
    EXPECT_EQ(ns(0, 0), 1.0f);
    EXPECT_EQ(ns(1, 1), 0.5f);
    EXPECT_EQ(ns(2, 2), 0.25f);
    // Singular (documented): falls back to the upper 3x3 itself, never NaN.
    Mat4 flat = scale(Vec3{1, 1, 0});
    Mat3 nf = normal_matrix(flat);
    EXPECT_TRUE(mat_near(nf, flat.upper3x3(), 0));
    EXPECT_TRUE(all_finite(nf));
}

}  // namespace
