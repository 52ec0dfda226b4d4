#include "sim/slab/cell_bounds.h"

#include <algorithm>
#include <cmath>

namespace mcref::volume {

namespace {

// The nearest float at most v, at least v.
float float_below(double v) {
  const float f = static_cast<float>(v);
  return f > v ? std::nextafter(f, -INFINITY) : f;
}
float float_above(double v) {
  const float f = static_cast<float>(v);
  return f < v ? std::nextafter(f, INFINITY) : f;
}

}  // namespace

CellBounds flatten_cell_bounds(const std::vector<LayerMajorants>& majorants, int depth_voxels) {
  CellBounds b;
  for (const LayerMajorants& M : majorants) {
    b.offset.push_back(b.lo.size());
    for (const double v : M.lo) b.lo.push_back(float_below(v));
    for (const double v : M.hi) b.hi.push_back(float_above(v));
    b.rho_max.push_back(*std::max_element(M.hi.begin(), M.hi.end()));
    b.depth_offset.push_back(b.depth_cell.size());
    const double top = M.faces.front(), hz = (M.faces.back() - top) / depth_voxels;
    for (int vz = 0; vz < depth_voxels; ++vz) {  // the depth cell holding the interval's middle
      const double middle = top + (vz + 0.5) * hz;
      b.depth_cell.push_back(static_cast<int>(std::upper_bound(M.faces.begin() + 1, M.faces.end() - 1, middle) - (M.faces.begin() + 1)));
    }
  }
  return b;
}

}  // namespace mcref::volume
