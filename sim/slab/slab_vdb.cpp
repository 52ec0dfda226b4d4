#include "sim/slab/slab_vdb.h"

#include "sim/files/vdb_file.h"

namespace mcref::volume {

namespace {
// The voxels i, j in [0, n), k in [0, nz] of `from`, converted to `To`'s value
// type, with its name, class, transform and metadata.
template <typename To, typename From>
typename To::Ptr periodic_copy(const From& from, int n, int nz) {
  auto to = To::create(typename To::ValueType(from.background()));
  to->setTransform(from.transform().copy());
  for (auto m = from.beginMeta(); m != from.endMeta(); ++m) to->insertMeta(m->first, *m->second);
  to->setName(from.getName());
  to->setGridClass(from.getGridClass());
  to->setVectorType(from.getVectorType());
  auto in = from.getConstAccessor();
  auto out = to->getAccessor();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k <= nz; ++k) {
        const openvdb::Coord c(i, j, k);
        out.setValue(c, typename To::ValueType(in.getValue(c)));
      }
  return to;
}
}  // namespace

openvdb::GridPtrVec export_grids(const DensityGrids& g) {
  const int n = g.geometry().grid.lateral_voxels, nz = g.geometry().grid.depth_voxels;
  openvdb::GridPtrVec out;
  for (std::size_t k = 0; k < g.grids().size(); ++k) {
    out.push_back(periodic_copy<openvdb::FloatGrid>(*g.grids()[k], n, nz));
    if (g.has_sggx(k)) {
      out.push_back(periodic_copy<openvdb::Vec3SGrid>(*g.s_diag(k), n, nz));
      out.push_back(periodic_copy<openvdb::Vec3SGrid>(*g.s_offdiag(k), n, nz));
    }
  }
  return out;
}

void write_vdb(const std::string& path, const DensityGrids& g) {
  const openvdb::GridPtrVec grids = export_grids(g);
  write_vdb_file(path, openvdb::GridCPtrVec(grids.begin(), grids.end()));
}

}  // namespace mcref::volume
