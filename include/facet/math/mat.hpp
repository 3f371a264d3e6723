// facet math: 3x3 and 4x4 float matrices for column vectors (v' = M * v), stored column-major,
// so m.col[c][r] is row r of column c and the memory layout matches OpenGL and GLM.
// The seeds' Direct3D matrices are row-vector forms: they are the transposes of these.
#pragma once

#include <optional>

#include "facet/api.hpp"
#include "facet/math/vec.hpp"

FACET_API_BEGIN
namespace facet {

struct Mat3 {
    Vec3 col[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

    static constexpr Mat3 identity() { return {}; }
    constexpr float operator()(int row, int column) const { return col[column][static_cast<std::size_t>(row)]; }
    constexpr float& operator()(int row, int column) { return col[column][static_cast<std::size_t>(row)]; }
};

struct Mat4 {
    Vec4 col[4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

    static constexpr Mat4 identity() { return {}; }
    static constexpr Mat4 zero() { return Mat4{{Vec4{}, Vec4{}, Vec4{}, Vec4{}}}; }
    // Builds from 16 values given row by row, as matrices are written on paper.
    static constexpr Mat4 from_rows(const float (&r)[16]) {
        Mat4 m;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) m(i, j) = r[i * 4 + j];
        return m;
    }
    constexpr float operator()(int row, int column) const { return col[column][static_cast<std::size_t>(row)]; }
    constexpr float& operator()(int row, int column) { return col[column][static_cast<std::size_t>(row)]; }
    constexpr Mat3 upper3x3() const {
        Mat3 m;
        for (int c = 0; c < 3; ++c) m.col[c] = col[c].xyz();
        return m;
    }
};

constexpr Vec3 operator*(const Mat3& m, Vec3 v) { return m.col[0] * v.x + m.col[1] * v.y + m.col[2] * v.z; }
constexpr Vec4 operator*(const Mat4& m, Vec4 v) {
    return m.col[0] * v.x + m.col[1] * v.y + m.col[2] * v.z + m.col[3] * v.w;
}
constexpr Mat3 operator*(const Mat3& a, const Mat3& b) {
    Mat3 r;
    for (int c = 0; c < 3; ++c) r.col[c] = a * b.col[c];
    return r;
}
constexpr Mat4 operator*(const Mat4& a, const Mat4& b) {
    Mat4 r;
    for (int c = 0; c < 4; ++c) r.col[c] = a * b.col[c];
    return r;
}
constexpr bool operator==(const Mat4& a, const Mat4& b) {
    for (int c = 0; c < 4; ++c)
        if (!(a.col[c] == b.col[c])) return false;
    return true;
}

// Transforms a point (w = 1) and a direction (w = 0) by an affine matrix.
constexpr Vec3 transform_point(const Mat4& m, Vec3 p) { return (m * Vec4(p, 1)).xyz(); }
constexpr Vec3 transform_direction(const Mat4& m, Vec3 d) { return (m * Vec4(d, 0)).xyz(); }

constexpr Mat3 transpose(const Mat3& m) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = m(j, i);
    return r;
}
constexpr Mat4 transpose(const Mat4& m) {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r(i, j) = m(j, i);
    return r;
}

float determinant(const Mat3& m);
float determinant(const Mat4& m);

// General inverse by cofactors. Returns nothing when the matrix is singular (or nearly so,
// relative to the size of its entries) or holds non-finite values.
std::optional<Mat3> inverse(const Mat3& m);
std::optional<Mat4> inverse(const Mat4& m);

// Inverse of an affine matrix [A t; 0 1]: inverse(A) and -inverse(A)·t. Cheaper than the general
// inverse; the caller promises the last row is (0, 0, 0, 1). Singular A or a non-finite translation
// gives nothing.
std::optional<Mat4> affine_inverse(const Mat4& m);

// The matrix that transforms normals: transpose(inverse(upper 3x3)). Falls back to the
// upper 3x3 itself when singular, so flattened objects still get some normal.
Mat3 normal_matrix(const Mat4& model);

}  // namespace facet
FACET_API_END
