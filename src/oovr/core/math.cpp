#include "oovr/core/math.h"

namespace oovr {

Mat4 translate(Vec3 t) {
  Mat4 r;
  r.at(0, 3) = t.x;
  r.at(1, 3) = t.y;
  r.at(2, 3) = t.z;
  return r;
}

Mat4 scale(Vec3 s) {
  Mat4 r;
  r.at(0, 0) = s.x;
  r.at(1, 1) = s.y;
  r.at(2, 2) = s.z;
  return r;
}

Mat4 rotate(Vec3 axis, float radians_) {
  const Vec3 a = normalize(axis);
  const double c = std::cos(double(radians_)), s = std::sin(double(radians_)), t = 1 - c;
  const double x = a.x, y = a.y, z = a.z;
  Mat4 r;
  r.at(0, 0) = float(t * x * x + c);
  r.at(0, 1) = float(t * x * y - s * z);
  r.at(0, 2) = float(t * x * z + s * y);
  r.at(1, 0) = float(t * x * y + s * z);
  r.at(1, 1) = float(t * y * y + c);
  r.at(1, 2) = float(t * y * z - s * x);
  r.at(2, 0) = float(t * x * z - s * y);
  r.at(2, 1) = float(t * y * z + s * x);
  r.at(2, 2) = float(t * z * z + c);
  return r;
}

Mat4 perspective(float fov_y, float aspect, float n, float f) {
  const double k = 1.0 / std::tan(double(fov_y) / 2);
  Mat4 r;
  r.at(0, 0) = float(k / aspect);
  r.at(1, 1) = float(k);
  r.at(2, 2) = float((double(f) + n) / (double(n) - f));
  r.at(2, 3) = float(2.0 * f * n / (double(n) - f));
  r.at(3, 2) = -1;
  r.at(3, 3) = 0;
  return r;
}

Mat4 look_at(Vec3 eye, Vec3 target, Vec3 up) {
  const Vec3 f = normalize(target - eye);
  const Vec3 s = normalize(cross(f, up));
  const Vec3 u = cross(s, f);
  Mat4 r;
  r.at(0, 0) = s.x;
  r.at(0, 1) = s.y;
  r.at(0, 2) = s.z;
  r.at(1, 0) = u.x;
  r.at(1, 1) = u.y;
  r.at(1, 2) = u.z;
  r.at(2, 0) = -f.x;
  r.at(2, 1) = -f.y;
  r.at(2, 2) = -f.z;
  r.at(0, 3) = -dot(s, eye);
  r.at(1, 3) = -dot(u, eye);
  r.at(2, 3) = dot(f, eye);
  return r;
}

bool invert(const Mat4& a, Mat4& out) {
  // Gauss-Jordan elimination with partial pivoting in double precision.
  double m[4][8];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      m[r][c] = a.at(r, c);
      m[r][c + 4] = r == c ? 1 : 0;
    }
  for (int c = 0; c < 4; ++c) {
    int p = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(m[r][c]) > std::abs(m[p][c])) p = r;
    if (std::abs(m[p][c]) < 1e-30) return false;
    if (p != c)
      for (int k = 0; k < 8; ++k) std::swap(m[p][k], m[c][k]);
    const double inv = 1.0 / m[c][c];
    for (int k = 0; k < 8; ++k) m[c][k] *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      const double f = m[r][c];
      for (int k = 0; k < 8; ++k) m[r][k] -= f * m[c][k];
    }
  }
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.at(r, c) = float(m[r][c + 4]);
  return true;
}

}  // namespace oovr
