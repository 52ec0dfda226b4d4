// geometry.density_vdb (sim/slab/density_vdb.h): densities read from an OpenVDB
// file laid out as export-vdb writes it. An exported slab reads back to the same
// grids and the same tables, bit for bit; voxels land where the file puts them;
// every malformed file is refused with its file, grid and voxel named.
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "sim/experiment/config_error.h"
#include "sim/files/vdb_file.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/slab_vdb.h"
#include "validate/model_evaluation.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

namespace {

const std::string kDir = ::testing::TempDir();

// Two layers: a tilted fibre layer over a surface layer, tile 2, 4 x 4 voxel
// columns, 8 voxel intervals per layer; `density` holds each layer's density keys
// (or nothing), `geometry_extra` more [geometry] keys.
std::string slab_text(const std::string& geometry_extra, const std::string& density0, const std::string& density1) {
  return R"([geometry]
kind = "slab"
backend = "openvdb"
tile = 2.0
lateral_voxels = 4
depth_voxels = 8
)" + geometry_extra + R"(
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.4
orientation_deg = [50, 20]
thickness = 0.5
albedo = 0.9
)" + density0 + R"(
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.3
thickness = 1.5
albedo = 0.8
)" + density1 + R"(
[run]
seed = 77
batches = 4
[[measure]]
quantity = "brdf"
theta_i_deg = [40]
phi_i_deg = [30]
theta_o_bins = 4
phi_bins = 4
samples = 3000
)";
}

Experiment from_file(const std::string& vdb, const std::string& extra = "") {
  return parse_experiment(slab_text("density_vdb = \"" + vdb + "\"\n" + extra, "", ""), kDir + "from_vdb.toml");
}

// A density grid of layer k of slab_text's geometry, value(i, j, z) on i, j in
// [0, 4), z in [0, 8], with the experiment's transform.
openvdb::FloatGrid::Ptr density_grid(int k, const std::function<float(int, int, int)>& value) {
  const double thickness = k == 0 ? 0.5 : 1.5, bottom = k == 0 ? 0.5 : 2.0;
  auto g = openvdb::FloatGrid::create(0.0f);
  g->setName("layer" + std::to_string(k) + "_density");
  auto xf = openvdb::math::Transform::createLinearTransform();
  xf->preScale(openvdb::Vec3d(0.5, 0.5, thickness / 8));
  xf->postTranslate(openvdb::Vec3d(0, 0, -bottom));
  g->setTransform(xf);
  auto acc = g->getAccessor();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int z = 0; z <= 8; ++z) acc.setValue(openvdb::Coord(i, j, z), value(i, j, z));
  return g;
}

float distinct(int i, int j, int z) { return static_cast<float>(1 + i + 10 * j + 100 * z); }

std::string write(const std::string& name, const openvdb::GridPtrVec& grids) {
  openvdb::initialize();
  const std::string path = kDir + name;
  write_vdb_file(path, openvdb::GridCPtrVec(grids.begin(), grids.end()));
  return path;
}

std::string two_layers(const std::string& name, const std::function<float(int, int, int)>& value = distinct) {
  return write(name, {density_grid(0, value), density_grid(1, value)});
}

// slab_text's geometry with an isotropic and an hg layer, densities from `file`.
Experiment isotropic_layers(const std::string& file) {
  return parse_experiment(R"([geometry]
kind = "slab"
backend = "openvdb"
tile = 2.0
lateral_voxels = 4
depth_voxels = 8
density_vdb = ")" + file + R"("
[[geometry.layer]]
phase = "isotropic"
thickness = 0.5
[[geometry.layer]]
phase = "hg"
g = 0.3
thickness = 1.5
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 1
)",
                          kDir + "iso.toml");
}

// `layers` without their density lines (what density_vdb replaces).
std::string without_density(std::string layers) {
  for (std::size_t at; (at = layers.find("density = ")) != std::string::npos;)
    layers.erase(at, layers.find('\n', at) + 1 - at);
  return layers;
}

// The ConfigError message of parsing `make()`, or "" if it parses.
std::string error_of(const std::function<Experiment()>& make) {
  try {
    make();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// export-vdb's file of a depth-profiled two-layer slab, read back as its
// densities: the same grids voxel for voxel, the same mean optical thickness
// (to float rounding), and the same tables, sum for sum.
TEST(SlabDensityVdb, ExportedSlabReadsBackToTheSameTables) {
  const Experiment original = parse_experiment(
      slab_text("", "density = 3.0\nprofile = \"linear\"\nprofile_top = 0.5\nprofile_bottom = 1.5\n",
                "optical_thickness = 2.0\nprofile = \"table\"\nprofile_table = [1, 3, 2]\n"),
      kDir + "original.toml");
  const std::string path = kDir + "exported.vdb";
  volume::write_vdb(path, volume::DensityGrids(original.slab));
  const Experiment imported = from_file(path);
  ASSERT_EQ(imported.slab.layers.size(), 2u);
  EXPECT_EQ(imported.isotropic, original.isotropic);  // the tilted fibre: not isotropic in either
  const volume::DensityGrids a(original.slab), b(imported.slab);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_FALSE(imported.slab.layers[k].varies_laterally);
    EXPECT_NEAR(imported.slab.layers[k].optical_thickness(), original.slab.layers[k].optical_thickness(),
                1e-6 * original.slab.layers[k].optical_thickness());
    auto ra = a.grids()[k]->getConstAccessor(), rb = b.grids()[k]->getConstAccessor();
    for (int i = 0; i <= 4; ++i)  // the seam column 4 too
      for (int j = 0; j <= 4; ++j)
        for (int z = 0; z <= 8; ++z) ASSERT_EQ(ra.getValue({i, j, z}), rb.getValue({i, j, z})) << k << " " << i << j << z;
  }
  const std::vector<Table> ta = slab_test::run(original), tb = slab_test::run(imported);
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t t = 0; t < ta.size(); ++t) {
    EXPECT_EQ(ta[t].sum, tb[t].sum) << ta[t].name;
    EXPECT_EQ(ta[t].sum_sq, tb[t].sum_sq) << ta[t].name;
  }
  EXPECT_GT(slab_test::find(ta, "brdf").batches, 0);
}

// Each voxel value lands at its (i, j, z), the seam column repeats column 0,
// the layer's density is the tile's mean, and a lateral variation makes the
// experiment anisotropic (no azimuth folding).
TEST(SlabDensityVdb, VoxelsLandWhereTheFilePutsThem) {
  const Experiment ex = from_file(two_layers("distinct.vdb"));
  const SlabLayer& l = ex.slab.layers[1];
  ASSERT_TRUE(l.voxels);
  EXPECT_TRUE(l.varies_laterally);
  EXPECT_FALSE(ex.isotropic);
  const volume::DensityGrids g(ex.slab);
  auto acc = g.grids()[1]->getConstAccessor();
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      for (int z = 0; z <= 8; ++z) {
        ASSERT_EQ(acc.getValue({i, j, z}), distinct(i % 4, j % 4, z));
        if (i < 4 && j < 4) ASSERT_EQ((*l.voxels)[(i * 4 + j) * 9 + z], distinct(i, j, z));
      }
  // Linear in i, j and z: the mean over the tile and the layer is at the means
  // i = j = 1.5 (columns 0..3) and z = 4 (the trapezoids of a linear column).
  EXPECT_DOUBLE_EQ(l.density, 1 + 1.5 + 15 + 400);
  EXPECT_DOUBLE_EQ(l.optical_thickness(), 1.5 * l.density);
}

// The provenance names the file's content, the path is taken relative to the
// experiment's folder, and a laterally varying imported slab gives the same sums
// on 1 and 2 threads.
TEST(SlabDensityVdb, ProvenanceRelativePathAndThreads) {
  const std::string path = two_layers("lateral.vdb", [](int i, int j, int z) {
    return static_cast<float>(2 + std::cos(1.5 * i) * std::cos(1.5 * j) + 0.1 * z);
  });
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const Experiment ex = from_file("lateral.vdb");  // beside from_vdb.toml, in kDir
  EXPECT_NE(ex.text.find("# geometry.density_vdb read from \"lateral.vdb\": bytes=" + std::to_string(in.tellg()) +
                         " fnv1a64="),
            std::string::npos)
      << ex.text;
  EXPECT_FALSE(ex.isotropic);
  // The text still parses, to the same text (the digest is a comment).
  EXPECT_EQ(parse_experiment(ex.text, kDir + "again.toml").text, ex.text);
  slab_test::expect_bit_identical_threads(ex);
}

// The wrong files and keys, each refused before any work with its file, key or
// grid, voxel and the allowed range.
TEST(SlabDensityVdb, RefusesWhatItCannotRead) {
  const std::string good = two_layers("good.vdb");
  const auto has = [](const std::string& message, const std::string& part) {
    EXPECT_NE(message.find(part), std::string::npos) << "\"" << part << "\" not in: " << message;
  };
  // The key itself.
  has(error_of([] { return from_file("missing.vdb"); }), "key 'geometry.density_vdb': '" + kDir + "missing.vdb' no such file");
  {
    std::ofstream(kDir + "text.vdb") << "not a vdb\n";
    const std::string m = error_of([] { return from_file("text.vdb"); });
    has(m, "from_vdb.toml: key 'geometry.density_vdb': '" + kDir + "text.vdb' is not a readable OpenVDB file");
  }
  has(error_of([&] {  // with a density key left in a layer: the backend is what is wrong
        std::string text = slab_text("density_vdb = \"" + good + "\"\n", "density = 1.0\n", "");
        text.replace(text.find("\"openvdb\""), 9, "\"homogeneous\"");
        return parse_experiment(text, "x.toml");
      }),
      "x.toml: key 'geometry.density_vdb': needs backend = \"openvdb\"");
  has(error_of([&] { return parse_experiment(slab_text("density_vdb = \"" + good + "\"\n", "density = 2.0\n", ""), "x.toml"); }),
      "key 'geometry.layer.0.density': the layer's density comes from geometry.density_vdb");
  has(error_of([&] { return parse_experiment(slab_text("density_vdb = \"" + good + "\"\n", "", "profile = \"linear\"\n"), "x.toml"); }),
      "key 'geometry.layer.1.profile'");
  // Laterally varying layers take the next-event estimators (escapes estimated, sim/slab/escape.h).
  EXPECT_EQ(error_of([&] { return from_file(good, "estimator = \"next_event\"\n"); }), "");
  // The grids.
  has(error_of([] { return from_file(write("one.vdb", {density_grid(0, distinct)})); }),
      "one.vdb: key 'layer1_density': no such grid (the experiment has 2 layers, one density grid each; the file holds: layer0_density)");
  {
    auto wrong = openvdb::DoubleGrid::create(1.0);
    wrong->setName("layer1_density");
    has(error_of([&] { return from_file(write("type.vdb", {density_grid(0, distinct), wrong})); }),
        "key 'layer1_density': is a Tree_double_5_4_3 grid; densities need a FloatGrid");
  }
  has(error_of([] { return from_file(two_layers("negative.vdb", [](int i, int j, int z) { return i == 1 && j == 2 && z == 3 ? -0.5f : 1.0f; })); }),
      "negative.vdb: key 'layer0_density': voxel (1, 2, 3) is -0.5; a density must be finite, in [0, 1e9]");
  has(error_of([] { return from_file(two_layers("nan.vdb", [](int i, int, int) { return i == 3 ? NAN : 1.0f; })); }),
      "voxel (3, 0, 0) is nan");
  has(error_of([] { return from_file(two_layers("thick.vdb", [](int, int, int) { return 1e8f; })); }),
      "key 'layer0_density': a column's optical thickness T rho is 50000000, more than 1e6");
  {
    auto seam = density_grid(1, distinct);
    seam->tree().setValue(openvdb::Coord(4, 0, 2), 1.0f);  // the periodic seam, stored
    has(error_of([&] { return from_file(write("seam.vdb", {density_grid(0, distinct), seam})); }),
        "key 'layer1_density': active voxel (4, 0, 2) lies outside i, j in [0, 4), k in [0, 8] (lateral_voxels 4, "
        "depth_voxels 8): the grid is larger than the experiment's, or it stores the periodic seam i or j = 4");
  }
  {
    auto shifted = density_grid(1, distinct);
    shifted->transform().postTranslate(openvdb::Vec3d(0, 0, 0.1));
    has(error_of([&] { return from_file(write("shifted.vdb", {density_grid(0, distinct), shifted})); }),
        "key 'layer1_density': its voxels are 0.5 x 0.5 x 0.1875 with voxel (0, 0, 0) at (0, 0, -1.9); the experiment "
        "needs axis-aligned voxels 0.5 x 0.5 x 0.1875 (tile 2 / lateral_voxels 4, thickness 1.5 / depth_voxels 8) with "
        "voxel (0, 0, 0) at (0, 0, -2)");
  }
  {
    auto other = openvdb::FloatGrid::create(0.0f);
    other->setName("temperature");
    has(error_of([&] { return from_file(write("extra.vdb", {density_grid(0, distinct), density_grid(1, distinct), other})); }),
        "key 'temperature': is not a grid the experiment reads");
  }
}

// S grids in the file must hold the experiment's S (export-vdb writes them):
// an edited S is refused, not ignored.
TEST(SlabDensityVdb, RefusesAnSThatIsNotTheExperiments) {
  const Experiment original = parse_experiment(slab_text("", "density = 3.0\n", "density = 1.0\n"), kDir + "o.toml");
  openvdb::GridPtrVec grids = volume::export_grids(volume::DensityGrids(original.slab));
  EXPECT_EQ(grids.size(), 6u);
  EXPECT_EQ(error_of([&] { return from_file(write("with_s.vdb", grids)); }), "");  // as exported: accepted
  for (auto& g : grids)
    if (g->getName() == "layer0_S_offdiag") {
      auto s = openvdb::gridPtrCast<openvdb::Vec3SGrid>(g);
      ASSERT_TRUE(s);
      s->tree().setValue(openvdb::Coord(2, 1, 5), openvdb::Vec3s(0.f, 0.f, 0.f));
    }
  const std::string m = error_of([&] { return from_file(write("edited_s.vdb", grids)); });
  EXPECT_NE(m.find("edited_s.vdb: key 'layer0_S_offdiag': voxel (2, 1, 5) holds (0, 0, 0), not the experiment's"),
            std::string::npos)
      << m;
}

// Files export-vdb writes are accepted whatever the geometry's scale (the
// transform is read from its matrix, not from differences of far-off points),
// and so is a transform stored in float32; a file exported with another tile
// is refused by its metadata, though its voxels have the experiment's size.
TEST(SlabDensityVdb, TransformsAndMetadata) {
  const auto round_trip = [](const std::string& name, const std::string& geometry, const std::string& layers) {
    const std::string head = "[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\n" + geometry;
    const std::string rest = "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 1\n";
    const Experiment original = parse_experiment(head + layers + rest, kDir + "o.toml");
    volume::write_vdb(kDir + name, volume::DensityGrids(original.slab));
    return error_of([&] {
      return parse_experiment(head + "density_vdb = \"" + name + "\"\n" + without_density(layers) + rest, kDir + "i.toml");
    });
  };
  // A thick, tenuous layer over a thin one: the thin layer's origin lies 3e7 deep. Its
  // grid moved by a tenth of a voxel is still refused there.
  const std::string deep = "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 3e7\ndensity = 1e-9\n"
                           "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 0.001\ndensity = 1000.0\n";
  EXPECT_EQ(round_trip("deep.vdb", "depth_voxels = 32\n", deep), "");
  {
    openvdb::io::File file(kDir + "deep.vdb");
    file.open();
    const openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();
    (*grids)[1]->transform().postTranslate(openvdb::Vec3d(0, 0, 0.1 * 0.001 / 32));
    write("deep.vdb", *grids);
    const std::string m = error_of([&] {
      return parse_experiment("[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\ndepth_voxels = 32\ndensity_vdb = \"deep.vdb\"\n" +
                                  without_density(deep) + "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 1\n",
                              kDir + "i.toml");
    });
    EXPECT_NE(m.find("deep.vdb: key 'layer1_density': its voxels are"), std::string::npos) << m;
  }
  // A zero-density layer (allowed by density = 0 too).
  EXPECT_EQ(round_trip("empty.vdb", "",
                       "[[geometry.layer]]\nphase = \"isotropic\"\ndensity = 0.0\n"
                       "[[geometry.layer]]\nphase = \"hg\"\ng = 0.5\ndensity = 2.0\n"),
            "");
  // Maps stored in float32, as some tools write them (0.3 / 64, 0.7 / 64 and 0.3 are not floats).
  {
    const std::string head = "[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\ntile = 0.7\ndepth_voxels = 64\n";
    const std::string layers = "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 0.3\n"
                               "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 0.7\n";
    const std::string rest = "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 1\n";
    const Experiment original = parse_experiment(head + layers + rest, kDir + "o.toml");
    openvdb::GridPtrVec grids = volume::export_grids(volume::DensityGrids(original.slab));
    for (std::size_t k = 0; k < 2; ++k) {
      const double hz = (k == 0 ? 0.3 : 0.7) / 64, bottom = k == 0 ? 0.3 : 1.0;
      auto xf = openvdb::math::Transform::createLinearTransform();
      xf->preScale(openvdb::Vec3d(static_cast<float>(0.7 / 4), static_cast<float>(0.7 / 4), static_cast<float>(hz)));
      xf->postTranslate(openvdb::Vec3d(0, 0, static_cast<float>(-bottom)));
      ASSERT_NE(xf->baseMap()->getAffineMap()->getMat4()(2, 2), hz);  // the test's point: rounded
      grids[k]->setTransform(xf);
    }
    write("float32.vdb", grids);
    EXPECT_EQ(error_of([&] { return parse_experiment(head + "density_vdb = \"float32.vdb\"\n" + layers + rest, kDir + "f.toml"); }), "");
  }
  // Exported from a tile of 1 with 2 voxels a side; read into a tile of 2 with 4 (voxels of the same size).
  const std::string small = kDir + "small_tile.vdb";
  {
    const Experiment e = parse_experiment(slab_text("", "density = 1.0\n", "density = 1.0\n"), kDir + "s.toml");
    Experiment half = e;
    half.slab.grid.tile = 1.0;
    half.slab.grid.lateral_voxels = 2;
    volume::write_vdb(small, volume::DensityGrids(half.slab));
  }
  const std::string m = error_of([&] { return from_file(small); });
  EXPECT_NE(m.find("small_tile.vdb: key 'layer0_density': its metadata lateral_period is 1 (as exported); the "
                   "experiment's geometry.tile is 2"),
            std::string::npos)
      << m;
}

// What the file may hold besides densities: S in double (Vec3DGrid) equal to
// the layer's; no S for a layer that is not SGGX; no grid twice.
TEST(SlabDensityVdb, SGridsAndNames) {
  const Experiment original = parse_experiment(slab_text("", "density = 3.0\n", "density = 1.0\n"), kDir + "o.toml");
  const volume::DensityGrids grids(original.slab);
  openvdb::GridPtrVec in_double;  // the simulation's own grids: S in double
  for (const auto& g : grids.all_grids()) in_double.push_back(g->deepCopyGrid());
  for (auto& g : in_double) {  // without the periodic seam, as a file holds them
    if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g)) f->clip(openvdb::CoordBBox({0, 0, 0}, {3, 3, 8}));
    if (auto d = openvdb::gridPtrCast<openvdb::Vec3DGrid>(g)) d->clip(openvdb::CoordBBox({0, 0, 0}, {3, 3, 8}));
  }
  EXPECT_EQ(error_of([&] { return from_file(write("double_s.vdb", in_double)); }), "");
  // An S grid beside an hg layer.
  auto s = openvdb::Vec3SGrid::create();
  s->setName("layer1_S_diag");
  const std::string hg = error_of([&] { return isotropic_layers(write("hg_s.vdb", {density_grid(0, distinct), density_grid(1, distinct), s})); });
  EXPECT_NE(hg.find("hg_s.vdb: key 'layer1_S_diag': layer 1 is not an SGGX layer: it has no S"), std::string::npos) << hg;
  auto dup = density_grid(0, distinct);
  const std::string m = error_of([&] { return from_file(write("twice.vdb", {density_grid(0, distinct), density_grid(1, distinct), dup})); });
  EXPECT_NE(m.find("twice.vdb: key 'layer0_density': two grids have this name"), std::string::npos) << m;
}

// A layer that varies in depth only keeps an isotropic sample isotropic (and
// flown exactly); a lateral variation makes the slab models unsupported.
TEST(SlabDensityVdb, IsotropyAndModels) {
  const Experiment depth_only = isotropic_layers(two_layers("depth_only.vdb", [](int, int, int z) { return 1.0f + z; }));
  EXPECT_TRUE(depth_only.isotropic);
  EXPECT_FALSE(depth_only.slab.layers[1].varies_laterally);
  EXPECT_EQ(slab_models().unsupported("spongecake_ss_brdf", depth_only), "");
  const Experiment lateral = isotropic_layers(two_layers("lateral_iso.vdb"));
  EXPECT_FALSE(lateral.isotropic);
  EXPECT_EQ(slab_models().unsupported("white_furnace", lateral),
            "white_furnace assumes laterally uniform layers; layer 0's density_vdb varies laterally");
}
