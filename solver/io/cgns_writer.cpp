#include "io/cgns_writer.hpp"

#include <cgnslib.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "core/error.hpp"

namespace narwhal {
namespace {

void check(int status, const std::string& what) {
  if (status != CG_OK) fail("CGNS: {} failed: {}", what, cg_get_error());
}

BCType_t cgns_bc(BcType t) {
  switch (t) {
    case BcType::Wall: return BCWallViscous;
    case BcType::Farfield: return BCFarfield;
    case BcType::Inflow: return BCInflow;
    case BcType::Outflow: return BCOutflow;
    case BcType::Symmetry: return BCSymmetryPlane;
    default: return BCGeneral;
  }
}

// Vertex range (1-based, CGNS) of a patch.
void patch_vertex_range(const Block& b, const Patch& p, cgsize_t range[6]) {
  const int d = side_dir(p.side);
  for (int t = 0; t < 3; ++t) {
    if (t == d) {
      range[t] = range[t + 3] = (side_high(p.side) ? b.n(d) : 0) + 1;
    } else {
      range[t] = p.lo[t] + 1;
      range[t + 3] = p.hi[t] + 1;
    }
  }
}

// Zones, coordinates, boundary patches and 1-to-1 connections of every block. Each
// boundary condition carries its patch label as FamilyName (and the base a Family_t
// per label), so that a reader maps patches back to the case's [bc.<label>] tables.
// A label that is also a zone's name cannot be a Family_t (zones and families share
// the base's names); its BCs are then named by the label alone where it occurs once
// in a zone.
std::vector<int> write_grid_nodes(int fn, int base, const Grid& g) {
  auto contains = [](const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
  };
  // Patches written as BCs: physical ones, and periodic pairs (recorded as general BCs).
  auto written_as_bc = [&g](const Patch& p) { return p.type != BcType::Interface || g.interfaces[p.interface].periodic; };
  std::vector<std::string> zone_names, families;
  for (const Block& b : g.blocks) zone_names.push_back(b.name);
  for (const Block& b : g.blocks)
    for (const Patch& p : b.patches)
      if (written_as_bc(p) && !contains(families, p.label) && !contains(zone_names, p.label))
        families.push_back(p.label);
  for (const std::string& name : families) {
    int fam = 0;
    check(cg_family_write(fn, base, name.c_str(), &fam), "family " + name);
  }
  std::vector<int> zones(g.blocks.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    cgsize_t size[9] = {b.ni + 1, b.nj + 1, b.nk + 1, b.ni, b.nj, b.nk, 0, 0, 0};
    check(cg_zone_write(fn, base, b.name.c_str(), size, Structured, &zones[ib]), "zone " + b.name);
    // Readers list zones by name; the ordinal keeps the block order (and with it the
    // run's sweep order) through a round trip.
    check(cg_goto(fn, base, "Zone_t", zones[ib], "end"), "zone " + b.name);
    check(cg_ordinal_write(static_cast<int>(ib) + 1), "ordinal of zone " + b.name);
  }
  std::vector<double> buf;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    const int zone = zones[ib];
    for (int c = 0; c < 3; ++c) {
      buf.clear();
      for (int k = 0; k <= b.nk; ++k)
        for (int j = 0; j <= b.nj; ++j)
          for (int i = 0; i <= b.ni; ++i) buf.push_back(b.x(i, j, k)[c]);
      int idx = 0;
      static const char* names[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
      check(cg_coord_write(fn, base, zone, RealDouble, names[c], buf.data(), &idx), "coordinates");
    }
    int nbc = 0, ncon = 0;
    auto write_bc = [&](const Patch& p, BCType_t type, const cgsize_t range[6]) {
      const auto uses = std::count_if(b.patches.begin(), b.patches.end(), [&](const Patch& q) {
        return q.label == p.label && written_as_bc(q);
      });
      const std::string name = uses == 1 ? p.label : fmt::format("{}_{}", p.label, nbc);
      ++nbc;
      int bc = 0;
      check(cg_boco_write(fn, base, zone, name.c_str(), type, PointRange, 2, range, &bc),
            "boundary condition " + p.label);
      if (!contains(families, p.label)) return;
      check(cg_goto(fn, base, "Zone_t", zone, "ZoneBC_t", 1, "BC_t", bc, "end"), "go to BC " + p.label);
      check(cg_famname_write(p.label.c_str()), "family name of " + p.label);
    };
    for (const Patch& p : b.patches) {
      cgsize_t range[6];
      patch_vertex_range(b, p, range);
      if (p.type != BcType::Interface) {
        write_bc(p, cgns_bc(p.type), range);
        continue;
      }
      const Interface& itf = g.interfaces[p.interface];
      if (itf.periodic) {
        // CGNS 1-to-1 periodic data needs a separate node; record the pair as a general BC.
        write_bc(p, BCGeneral, range);
        continue;
      }
      const Block& d = g.blocks[itf.donor];
      cgsize_t donor[6];
      const Index3 a_lo{static_cast<int>(range[0] - 1), static_cast<int>(range[1] - 1), static_cast<int>(range[2] - 1)};
      const Index3 a_hi{static_cast<int>(range[3] - 1), static_cast<int>(range[4] - 1), static_cast<int>(range[5] - 1)};
      const Index3 b_lo = itf.map_node(a_lo), b_hi = itf.map_node(a_hi);
      for (int t = 0; t < 3; ++t) {
        donor[t] = b_lo[t] + 1;
        donor[t + 3] = b_hi[t] + 1;
      }
      int transform[3];
      for (int m = 0; m < 3; ++m)
        for (int n = 0; n < 3; ++n)
          if (itf.T(n, m) != 0) transform[m] = itf.T(n, m) * (n + 1);
      int con = 0;
      // Named by number: CGNS names hold 32 characters, "interface:<donor>" can be longer.
      check(cg_1to1_write(fn, base, zone, fmt::format("connection_{}", ncon++).c_str(), d.name.c_str(), range,
                          donor, transform, &con),
            "1-to-1 connection");
    }
  }
  return zones;
}

// Writes to a temporary file and renames it, so that a reader never sees half a file.
template <class Body>
void write_cgns_file(const std::string& path, Body&& body) {
  const std::string tmp = path + ".tmp";
  int fn = 0, base = 0;
  check(cg_open(tmp.c_str(), CG_MODE_WRITE, &fn), "open " + tmp);
  check(cg_base_write(fn, "Base", 3, 3, &base), "base");
  body(fn, base);
  check(cg_close(fn), "close");
  std::filesystem::rename(tmp, path);
}

}  // namespace

void write_cgns_grid(const std::string& path, const Grid& g) {
  write_cgns_file(path, [&](int fn, int base) { write_grid_nodes(fn, base, g); });
}

void write_cgns_solution(const std::string& path, const Grid& g, const FlowField& f,
                         const std::vector<std::string>& turbulence, Real nu_laminar) {
  write_cgns_file(path, [&](int fn, int base) {
    const std::vector<int> zones = write_grid_nodes(fn, base, g);
    std::vector<double> buf;
    for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
      const Block& b = g.blocks[ib];
      const int zone = zones[ib];
      int sol = 0;
      check(cg_sol_write(fn, base, zone, "FlowSolution", CellCenter, &sol), "solution node");
      auto write_cell_field = [&](const std::string& name, auto value) {
        buf.clear();
        for (int k = 0; k < b.nk; ++k)
          for (int j = 0; j < b.nj; ++j)
            for (int i = 0; i < b.ni; ++i) buf.push_back(value(i, j, k));
        int fld = 0;
        check(cg_field_write(fn, base, zone, sol, RealDouble, name.c_str(), buf.data(), &fld), "field " + name);
      };
      static const char* fields[4] = {"Pressure", "VelocityX", "VelocityY", "VelocityZ"};
      for (int m = 0; m < kNumEq; ++m)
        write_cell_field(fields[m], [&](int i, int j, int k) { return f.Q[ib](i, j, k)[m]; });
      for (std::size_t m = 0; m < turbulence.size() && !f.turb.empty(); ++m)
        write_cell_field(turbulence[m], [&](int i, int j, int k) { return f.turb[ib](i, j, k)[m]; });
      if (!turbulence.empty())
        write_cell_field("ViscosityEddyKinematic", [&](int i, int j, int k) { return f.nu[ib](i, j, k) - nu_laminar; });
    }
  });
}

}  // namespace narwhal
