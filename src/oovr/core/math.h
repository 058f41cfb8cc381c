// Small fixed-size vector and matrix types for the scene model and the
// functional pipeline. Deliberately tiny (no glm in hot include paths) and
// explicit about evaluation order: the reference renderer evaluates the same
// products in the same order, which keeps vertex positions bit-comparable.
#pragma once

#include <cmath>
#include <cstdint>

namespace oovr {

struct Vec2 {
  float x = 0, y = 0;
};

struct Vec3 {
  float x = 0, y = 0, z = 0;
  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
  friend Vec3 operator*(float s, Vec3 a) { return a * s; }
};

struct Vec4 {
  float x = 0, y = 0, z = 0, w = 0;
};

inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) {
  const float l = length(a);
  return l > 0 ? a * (1.0f / l) : a;
}
inline Vec3 lerp(Vec3 a, Vec3 b, float t) { return a + (b - a) * t; }

// Column-major 4x4 matrix, m[column][row], as OpenGL stores it, so a Mat4 can
// be handed to glUniformMatrix4fv without transposition.
struct Mat4 {
  float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

  static Mat4 identity() { return {}; }
  float& at(int row, int col) { return m[col][row]; }
  float at(int row, int col) const { return m[col][row]; }
};

// Matrix products are formed in double and rounded once: the composed matrix
// (e.g. clip_from_world) is then an exact input shared with the reference.
inline Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += double(a.at(row, k)) * double(b.at(k, c));
      r.at(row, c) = float(s);
    }
  return r;
}

// Matrix times point, evaluated as the GLSL expression `M * vec4(p, 1)`:
// column by column, multiply then add, left to right, single precision.
inline Vec4 transform_point(const Mat4& a, Vec3 p) {
  Vec4 r;
  r.x = a.m[0][0] * p.x + a.m[1][0] * p.y + a.m[2][0] * p.z + a.m[3][0];
  r.y = a.m[0][1] * p.x + a.m[1][1] * p.y + a.m[2][1] * p.z + a.m[3][1];
  r.z = a.m[0][2] * p.x + a.m[1][2] * p.y + a.m[2][2] * p.z + a.m[3][2];
  r.w = a.m[0][3] * p.x + a.m[1][3] * p.y + a.m[2][3] * p.z + a.m[3][3];
  return r;
}

// Matrix times direction: GLSL's `mat3(M) * d`.
inline Vec3 transform_direction(const Mat4& a, Vec3 d) {
  return {a.m[0][0] * d.x + a.m[1][0] * d.y + a.m[2][0] * d.z, a.m[0][1] * d.x + a.m[1][1] * d.y + a.m[2][1] * d.z,
          a.m[0][2] * d.x + a.m[1][2] * d.y + a.m[2][2] * d.z};
}

inline Vec3 transform_point3(const Mat4& a, Vec3 p) {
  const Vec4 r = transform_point(a, p);
  return {r.x, r.y, r.z};
}

Mat4 translate(Vec3 t);
Mat4 scale(Vec3 s);
// Rotation by `radians` about the unit axis (right-handed).
Mat4 rotate(Vec3 axis, float radians);
// OpenGL-style perspective projection (eye looks down -Z, depth to [-1, 1]).
Mat4 perspective(float fov_y_radians, float aspect, float z_near, float z_far);
// View matrix: eye_from_world for a camera at `eye` looking at `target`.
Mat4 look_at(Vec3 eye, Vec3 target, Vec3 up);
// General inverse (double precision inside); returns false when singular.
bool invert(const Mat4& a, Mat4& out);

constexpr float kPi = 3.14159265358979323846f;
inline float radians(float degrees) { return degrees * (kPi / 180.0f); }

}  // namespace oovr
