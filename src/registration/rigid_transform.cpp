// RigidTransform, its text form and transformCloud (rigid_transform.h).
#include "registration/rigid_transform.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>

#include "core/error.h"

namespace parallax {

namespace {

bool parseNumber(const std::string& word, double& value) {
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  return error == std::errc() && end == word.data() + word.size();
}

}  // namespace

RigidTransform RigidTransform::translation(double x, double y, double z) {
  RigidTransform t;
  t.m[0][3] = x;
  t.m[1][3] = y;
  t.m[2][3] = z;
  return t;
}

RigidTransform RigidTransform::rotation(double x, double y, double z, double degrees) {
  const double len = std::sqrt(x * x + y * y + z * z);
  x /= len;
  y /= len;
  z /= len;
  const double a = degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a),
               k = 1.0 - c;
  RigidTransform r;
  r.m[0] = {c + x * x * k, x * y * k - z * s, x * z * k + y * s, 0};
  r.m[1] = {y * x * k + z * s, c + y * y * k, y * z * k - x * s, 0};
  r.m[2] = {z * x * k - y * s, z * y * k + x * s, c + z * z * k, 0};
  return r;
}

RigidTransform RigidTransform::fromEuler(double alpha, double beta, double gamma) {
  const double ca = std::cos(alpha), sa = std::sin(alpha), cb = std::cos(beta), sb = std::sin(beta),
               cg = std::cos(gamma), sg = std::sin(gamma);
  RigidTransform r;
  r.m[0] = {cg * cb, -sg * ca + cg * sb * sa, sg * sa + cg * sb * ca, 0};
  r.m[1] = {sg * cb, cg * ca + sg * sb * sa, -cg * sa + sg * sb * ca, 0};
  r.m[2] = {-sb, cb * sa, cb * ca, 0};
  return r;
}

RigidTransform RigidTransform::operator*(const RigidTransform& first) const {
  RigidTransform out;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      double sum = 0.0;
      for (int k = 0; k < 4; ++k) sum += m[i][k] * first.m[k][j];
      out.m[i][j] = sum;
    }
  }
  return out;
}

RigidTransform RigidTransform::inverse() const {
  RigidTransform out;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.m[i][j] = m[j][i];
  }
  for (int i = 0; i < 3; ++i) {
    out.m[i][3] = -(out.m[i][0] * m[0][3] + out.m[i][1] * m[1][3] + out.m[i][2] * m[2][3]);
  }
  return out;
}

std::array<double, 3> RigidTransform::apply(const std::array<double, 3>& p) const {
  std::array<double, 3> out;
  for (int i = 0; i < 3; ++i) {
    out[std::size_t(i)] = m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3];
  }
  return out;
}

std::array<double, 3> RigidTransform::rotate(const std::array<double, 3>& v) const {
  std::array<double, 3> out;
  for (int i = 0; i < 3; ++i)
    out[std::size_t(i)] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
  return out;
}

double RigidTransform::angleDegrees() const {
  const double c = std::clamp((m[0][0] + m[1][1] + m[2][2] - 1.0) / 2.0, -1.0, 1.0);
  // acos loses digits near 0; the skew part gives the sine there.
  const double sx = m[2][1] - m[1][2], sy = m[0][2] - m[2][0], sz = m[1][0] - m[0][1];
  const double s = 0.5 * std::sqrt(sx * sx + sy * sy + sz * sz);
  return std::atan2(s, c) * 180.0 / std::numbers::pi;
}

double RigidTransform::translationLength() const {
  return std::sqrt(m[0][3] * m[0][3] + m[1][3] * m[1][3] + m[2][3] * m[2][3]);
}

RigidTransform parseRigidTransform(const std::string& text, const std::string& source) {
  RigidTransform t;
  std::istringstream in(text);
  std::string line;
  int row = 0, line_number = 0, last_line = 0;
  while (std::getline(in, line)) {
    ++line_number;
    for (char& c : line) {
      if (c == ',' || c == '\t' || c == '\r') c = ' ';
    }
    const auto first = line.find_first_not_of(' ');
    if (first == std::string::npos || line[first] == '#') continue;
    if (row == 4) {
      throw InputError({.file = source,
                        .line = std::uint64_t(line_number),
                        .expected = "four rows of four numbers (a 4x4 matrix)",
                        .found = "a fifth row: " + quoteInput(line)});
    }
    std::istringstream numbers(line);
    std::string word;
    int column = 0;
    while (numbers >> word) {
      double v = 0.0;
      if (column == 4 || !parseNumber(word, v) || !std::isfinite(v)) {
        throw InputError({.file = source,
                          .line = std::uint64_t(line_number),
                          .expected = "four numbers on row " + std::to_string(row + 1),
                          .found = column == 4 ? "more: " + quoteInput(line) : quoteInput(word)});
      }
      t.m[row][column++] = v;
    }
    if (column != 4) {
      throw InputError({.file = source,
                        .line = std::uint64_t(line_number),
                        .expected = "four numbers on row " + std::to_string(row + 1),
                        .found = std::to_string(column)});
    }
    ++row;
    last_line = line_number;
  }
  if (row != 4) {
    throw InputError({.file = source,
                      .line = std::uint64_t(line_number),
                      .expected = "four rows of four numbers (a 4x4 matrix)",
                      .found = std::to_string(row) + " rows"});
  }
  if (t.m[3][0] != 0.0 || t.m[3][1] != 0.0 || t.m[3][2] != 0.0 || t.m[3][3] != 1.0) {
    throw InputError({.file = source,
                      .line = std::uint64_t(last_line),
                      .expected = "a last row of 0 0 0 1 (a rigid transform)",
                      .found = "another last row"});
  }
  double worst = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double dot = 0.0;
      for (int k = 0; k < 3; ++k) dot += t.m[k][i] * t.m[k][j];
      worst = std::max(worst, std::abs(dot - (i == j ? 1.0 : 0.0)));
    }
  }
  const double det = t.m[0][0] * (t.m[1][1] * t.m[2][2] - t.m[1][2] * t.m[2][1]) -
                     t.m[0][1] * (t.m[1][0] * t.m[2][2] - t.m[1][2] * t.m[2][0]) +
                     t.m[0][2] * (t.m[1][0] * t.m[2][1] - t.m[1][1] * t.m[2][0]);
  if (worst > 1e-6 || det < 0.0) {
    throw InputError(
        {.file = source,
         .expected = "a rotation in the upper 3x3 part (orthonormal, determinant 1)",
         .found = det < 0.0 ? "a reflection" : "R^T R off the identity by " + std::to_string(worst),
         .hint = "write rotation and translation only, no scale"});
  }
  return t;
}

RigidTransform readRigidTransform(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError({.file = path.string(),
                      .expected = "a readable 4x4 matrix file",
                      .found = "no such file or no permission"});
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parseRigidTransform(text.str(), path.string());
}

std::string formatRigidTransform(const RigidTransform& transform) {
  std::string out;
  char buffer[40];
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      std::snprintf(buffer, sizeof buffer, "%.17g", transform.m[i][j]);
      out += buffer;
      out += j == 3 ? "\n" : " ";
    }
  }
  return out;
}

void transformCloud(PointCloud& cloud, const RigidTransform& transform) {
  // The offset follows the translation in whole steps of the scale, so the integers stay near
  // where they were; the rotation about the old offset moves them by the cloud's own extent.
  Quantization moved = cloud.quantization;
  const std::array<double, 3> centre = transform.apply(
      {cloud.quantization.offset[0], cloud.quantization.offset[1], cloud.quantization.offset[2]});
  for (int a = 0; a < 3; ++a) moved.offset[std::size_t(a)] = centre[std::size_t(a)];
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const std::array<double, 3> p =
        transform.apply({cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i)});
    for (int a = 0; a < 3; ++a) {
      if (!moved.fits(a, p[std::size_t(a)])) {
        throw std::runtime_error(
            "register: a moved point does not fit the cloud's 32-bit "
            "positions at its scale; write a format with double positions");
      }
    }
    cloud.positions[i] = {moved.toQuantized(0, p[0]), moved.toQuantized(1, p[1]),
                          moved.toQuantized(2, p[2])};
  }
  cloud.quantization = moved;
  if (cloud.hasNormals()) {
    for (std::size_t i = 0; i < cloud.count; ++i) {
      Float3& n = cloud.normals[i];
      const std::array<double, 3> r = transform.rotate({n.x, n.y, n.z});
      n = {float(r[0]), float(r[1]), float(r[2])};
    }
  }
  cloud.computeBounds();
}

}  // namespace parallax
