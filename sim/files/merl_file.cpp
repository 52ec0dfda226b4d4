#include "sim/files/merl_file.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "sim/files/temp_file.h"

namespace mcref {

namespace {
// MERL's rotate_vector: v rotated by `angle` about the unit `axis` (Rodrigues).
Vec3 rotate(Vec3 v, Vec3 axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + axis * (dot(v, axis) * (1 - c)) + cross(axis, v) * s;
}
}  // namespace

void merl_directions(int i, int j, int k, Vec3& wi, Vec3& wo) {
  const double theta_h = (double(i) / kMerlThetaH) * (double(i) / kMerlThetaH) * (kPi / 2);
  const double theta_d = j * (kPi / 2) / kMerlThetaD, phi_d = k * kPi / kMerlPhiD;
  const Vec3 h{std::sin(theta_h), 0, std::cos(theta_h)};
  const Vec3 d{std::sin(theta_d) * std::cos(phi_d), std::sin(theta_d) * std::sin(phi_d), std::cos(theta_d)};
  // MERL's half_diff_coords_to_std_coords with phi_h = 0: rotate d about the binormal y by theta_h.
  wi = rotate(d, Vec3{0, 1, 0}, theta_h);
  wo = h * (2 * dot(wi, h)) - wi;
}

void write_merl_file(const std::string& path, const std::array<std::vector<double>, 3>& rgb) {
  for (const auto& c : rgb)
    if (c.size() != kMerlCells) throw std::invalid_argument("MERL data must have 90 x 90 x 180 values per channel");
  const std::int32_t dims[3] = {kMerlThetaH, kMerlThetaD, kMerlPhiD};
  std::string bytes(sizeof dims + 3 * kMerlCells * sizeof(double), '\0');
  std::memcpy(bytes.data(), dims, sizeof dims);
  char* out = bytes.data() + sizeof dims;
  for (int c = 0; c < 3; ++c)
    for (std::size_t n = 0; n < kMerlCells; ++n) {
      const double v = rgb[c][n] / kMerlScale[c];
      std::memcpy(out, &v, sizeof v);
      out += sizeof v;
    }
  write_text_file(path, bytes);
}

}  // namespace mcref
