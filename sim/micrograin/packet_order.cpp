#include "sim/micrograin/packet_order.h"

#include <algorithm>

namespace mcref {

namespace {
// The bits of x (< 2^8) spread to the even bit positions, for every x.
struct SpreadBits {
  std::uint16_t of[256];
  constexpr SpreadBits() : of() {
    for (std::uint32_t x = 0; x < 256; ++x) {
      std::uint32_t y = (x | (x << 4)) & 0x0F0Fu;
      y = (y | (y << 2)) & 0x3333u;
      of[x] = static_cast<std::uint16_t>((y | (y << 1)) & 0x5555u);
    }
  }
};
constexpr SpreadBits kSpread;
}  // namespace

void packet_order(const Vec3* origins, std::size_t n, double side_x, double side_y, std::size_t per_cell,
                  std::vector<std::uint32_t>& order, std::vector<Vec3>& sorted, std::vector<std::uint32_t>& cells) {
  int level = 0;  // 2^level cells per side, at most 256
  while (level < 8 && (std::size_t{1} << (2 * level)) * per_cell < n) ++level;
  const int g = 1 << level;
  const double sx = g / side_x, sy = g / side_y;
  std::vector<std::uint32_t> count(static_cast<std::size_t>(g) * g + 1, 0);
  cells.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const int ix = std::clamp(static_cast<int>(origins[k].x * sx), 0, g - 1);
    const int iy = std::clamp(static_cast<int>(origins[k].y * sy), 0, g - 1);
    cells[k] = kSpread.of[ix] | static_cast<std::uint32_t>(kSpread.of[iy]) << 1;
    ++count[cells[k] + 1];
  }
  for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
  order.resize(n);
  sorted.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = count[cells[k]]++;
    order[i] = static_cast<std::uint32_t>(k);
    sorted[i] = origins[k];
  }
}

}  // namespace mcref
