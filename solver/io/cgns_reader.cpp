#include "io/cgns_reader.hpp"

#include <cgnslib.h>

#include <algorithm>
#include <filesystem>
#include <utility>

#include "core/error.hpp"

namespace narwhal {
namespace {

class CgnsFile {
 public:
  explicit CgnsFile(const std::string& path) : path_(path) {
    if (!std::filesystem::exists(path)) fail("{}: no such file", path);
    if (cg_open(path.c_str(), CG_MODE_READ, &fn_) != CG_OK) fail("{}: not a readable CGNS file: {}", path, cg_get_error());
  }
  ~CgnsFile() { cg_close(fn_); }
  CgnsFile(const CgnsFile&) = delete;
  CgnsFile& operator=(const CgnsFile&) = delete;
  int fn() const { return fn_; }
  void check(int status, const std::string& what) const {
    if (status != CG_OK) fail("{}: {}: {}", path_, what, cg_get_error());
  }

 private:
  std::string path_;
  int fn_ = 0;
};

// The side of a zone a vertex range lies on (-1: not a single face), from which
// index is constant and at a zone end.
int face_side(const cgsize_t r[6], const Index3& cells) {
  int side = -1;
  for (int d = 0; d < 3; ++d) {
    if (r[d] != r[d + 3]) continue;
    if (side >= 0) return -1;  // an edge or a point
    if (r[d] == 1) side = 2 * d;
    else if (r[d] == cells[d] + 1) side = 2 * d + 1;
    else return -1;  // a plane inside the zone
  }
  return side;
}

Block read_zone(const CgnsFile& f, const std::string& path, int base, int zone) {
  char name[33] = {};
  cgsize_t size[9] = {};
  ZoneType_t type{};
  f.check(cg_zone_type(f.fn(), base, zone, &type), fmt::format("zone {}", zone));
  f.check(cg_zone_read(f.fn(), base, zone, name, size), fmt::format("zone {}", zone));
  if (type != Structured) fail("{}: zone '{}' is unstructured; Narwhal reads structured zones only", path, name);
  int dim = 0;
  f.check(cg_index_dim(f.fn(), base, zone, &dim), fmt::format("zone '{}'", name));
  if (dim != 3) fail("{}: zone '{}' has index dimension {}; expected 3", path, name, dim);
  check_block_size(fmt::format("{}: zone '{}'", path, name), size[3], size[4], size[5]);
  Block b(name, static_cast<int>(size[3]), static_cast<int>(size[4]), static_cast<int>(size[5]));
  const std::size_t nodes = static_cast<std::size_t>(size[0] * size[1] * size[2]);
  std::vector<double> xyz[3];
  cgsize_t lo[3] = {1, 1, 1}, hi[3] = {size[0], size[1], size[2]};
  static const char* names[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
  for (int c = 0; c < 3; ++c) {
    xyz[c].resize(nodes);
    f.check(cg_coord_read(f.fn(), base, zone, names[c], RealDouble, lo, hi, xyz[c].data()),
            fmt::format("zone '{}': {}", name, names[c]));
  }
  std::size_t n = 0;
  for (int k = 0; k <= b.nk; ++k)
    for (int j = 0; j <= b.nj; ++j)
      for (int i = 0; i <= b.ni; ++i, ++n) {
        const Vec3 x(xyz[0][n], xyz[1][n], xyz[2][n]);
        if (!x.allFinite()) fail("{}: zone '{}': node ({}, {}, {}) is not finite", path, name, i, j, k);
        b.x(i, j, k) = x;
      }
  int nbc = 0;
  f.check(cg_nbocos(f.fn(), base, zone, &nbc), fmt::format("zone '{}': boundary conditions", name));
  for (int bc = 1; bc <= nbc; ++bc) {
    char bc_name[33] = {};
    BCType_t bc_type{};
    PointSetType_t set{};
    cgsize_t npts = 0, normal_list = 0;
    int normal_index[3] = {}, ndatasets = 0;
    DataType_t normal_type{};
    f.check(cg_boco_info(f.fn(), base, zone, bc, bc_name, &bc_type, &set, &npts, normal_index, &normal_list,
                         &normal_type, &ndatasets),
            fmt::format("zone '{}': BC {}", name, bc));
    GridLocation_t location = Vertex;
    f.check(cg_boco_gridlocation_read(f.fn(), base, zone, bc, &location), fmt::format("zone '{}': BC '{}'", name, bc_name));
    if (set != PointRange || npts != 2 || location != Vertex)
      fail("{}: zone '{}': BC '{}': expected a vertex PointRange (a rectangle of one zone face); PointList and "
           "face-centred ranges are not supported", path, name, bc_name);
    cgsize_t r[6] = {};
    f.check(cg_boco_read(f.fn(), base, zone, bc, r, nullptr), fmt::format("zone '{}': BC '{}'", name, bc_name));
    for (int d = 0; d < 3; ++d)
      if (r[d] > r[d + 3]) std::swap(r[d], r[d + 3]);
    const int side = face_side(r, b.dims());
    if (side < 0)
      fail("{}: zone '{}': BC '{}': range ({}, {}, {}) - ({}, {}, {}) is not a rectangle on one face of the zone "
           "({} x {} x {} nodes)", path, name, bc_name, r[0], r[1], r[2], r[3], r[4], r[5], b.ni + 1, b.nj + 1, b.nk + 1);
    Patch p;
    p.side = side;
    for (int t = 0; t < 3; ++t) {
      if (t == side_dir(side)) continue;
      p.lo[t] = static_cast<int>(r[t] - 1);
      p.hi[t] = static_cast<int>(r[t + 3] - 1);
      if (p.lo[t] < 0 || p.hi[t] > b.n(t) || p.lo[t] >= p.hi[t])
        fail("{}: zone '{}': BC '{}': range in {} runs from node {} to {}; the zone has {} nodes there", path, name,
             bc_name, "ijk"[t], r[t], r[t + 3], b.n(t) + 1);
    }
    char family[33] = {};
    f.check(cg_goto(f.fn(), base, "Zone_t", zone, "ZoneBC_t", 1, "BC_t", bc, "end"), fmt::format("zone '{}': BC '{}'", name, bc_name));
    const int has_family = cg_famname_read(family);
    p.label = has_family == CG_OK && family[0] != '\0' ? family : bc_name;
    b.patches.push_back(p);
  }
  return b;
}

}  // namespace

std::vector<Block> read_cgns_grid(const std::string& path) {
  const CgnsFile f(path);
  int bases = 0;
  f.check(cg_nbases(f.fn(), &bases), "bases");
  if (bases < 1) fail("{}: the file has no CGNS base", path);
  constexpr int base = 1;
  char base_name[33] = {};
  int cell_dim = 0, phys_dim = 0;
  f.check(cg_base_read(f.fn(), base, base_name, &cell_dim, &phys_dim), "base 1");
  if (cell_dim != 3 || phys_dim != 3)
    fail("{}: base '{}' has cell dimension {} and physical dimension {}; expected a 3-D grid", path, base_name,
         cell_dim, phys_dim);
  int zones = 0;
  f.check(cg_nzones(f.fn(), base, &zones), "zones");
  if (zones < 1) fail("{}: base '{}' has no zones", path, base_name);
  // Zones in the order of their Ordinal_t when every zone has one (Narwhal writes
  // them: the CGNS library lists zones by name), else in the file's order.
  std::vector<std::pair<int, int>> order;  // (ordinal, zone)
  bool ordered = true;
  for (int z = 1; z <= zones; ++z) {
    int ordinal = 0;
    f.check(cg_goto(f.fn(), base, "Zone_t", z, "end"), fmt::format("zone {}", z));
    ordered = ordered && cg_ordinal_read(&ordinal) == CG_OK;
    order.emplace_back(ordinal, z);
  }
  if (ordered) std::stable_sort(order.begin(), order.end());
  std::vector<Block> blocks;
  for (const auto& [ordinal, z] : order) blocks.push_back(read_zone(f, path, base, z));
  return blocks;
}

}  // namespace narwhal
