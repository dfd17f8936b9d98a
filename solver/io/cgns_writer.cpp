#include "io/cgns_writer.hpp"

#include <cgnslib.h>

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

}  // namespace

void write_cgns_solution(const std::string& path, const Grid& g, const FlowField& f,
                         const std::vector<std::string>& turbulence, Real nu_laminar) {
  const std::string tmp = path + ".tmp";
  int fn = 0, base = 0;
  check(cg_open(tmp.c_str(), CG_MODE_WRITE, &fn), "open " + tmp);
  check(cg_base_write(fn, "Base", 3, 3, &base), "base");
  std::vector<int> zones(g.blocks.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    cgsize_t size[9] = {b.ni + 1, b.nj + 1, b.nk + 1, b.ni, b.nj, b.nk, 0, 0, 0};
    check(cg_zone_write(fn, base, b.name.c_str(), size, Structured, &zones[ib]), "zone " + b.name);
  }
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    const int zone = zones[ib];
    std::vector<double> buf;
    for (int c = 0; c < 3; ++c) {
      buf.clear();
      for (int k = 0; k <= b.nk; ++k)
        for (int j = 0; j <= b.nj; ++j)
          for (int i = 0; i <= b.ni; ++i) buf.push_back(b.x(i, j, k)[c]);
      int idx = 0;
      static const char* names[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
      check(cg_coord_write(fn, base, zone, RealDouble, names[c], buf.data(), &idx), "coordinates");
    }
    int sol = 0;
    check(cg_sol_write(fn, base, zone, "FlowSolution", CellCenter, &sol), "solution node");
    static const char* fields[4] = {"Pressure", "VelocityX", "VelocityY", "VelocityZ"};
    for (int m = 0; m < kNumEq; ++m) {
      buf.clear();
      for (int k = 0; k < b.nk; ++k)
        for (int j = 0; j < b.nj; ++j)
          for (int i = 0; i < b.ni; ++i) buf.push_back(f.Q[ib](i, j, k)[m]);
      int fld = 0;
      check(cg_field_write(fn, base, zone, sol, RealDouble, fields[m], buf.data(), &fld), "field");
    }
    auto write_cell_field = [&](const std::string& name, auto value) {
      buf.clear();
      for (int k = 0; k < b.nk; ++k)
        for (int j = 0; j < b.nj; ++j)
          for (int i = 0; i < b.ni; ++i) buf.push_back(value(i, j, k));
      int fld = 0;
      check(cg_field_write(fn, base, zone, sol, RealDouble, name.c_str(), buf.data(), &fld), "field " + name);
    };
    for (std::size_t m = 0; m < turbulence.size() && !f.turb.empty(); ++m)
      write_cell_field(turbulence[m], [&](int i, int j, int k) { return f.turb[ib](i, j, k)[m]; });
    if (!turbulence.empty())
      write_cell_field("ViscosityEddyKinematic", [&](int i, int j, int k) { return f.nu[ib](i, j, k) - nu_laminar; });
    int nbc = 0, ncon = 0;
    for (const Patch& p : b.patches) {
      cgsize_t range[6];
      patch_vertex_range(b, p, range);
      if (p.type == BcType::Interface) {
        const Interface& itf = g.interfaces[p.interface];
        const Block& d = g.blocks[itf.donor];
        cgsize_t donor[6];
        const Index3 a_lo{static_cast<int>(range[0] - 1), static_cast<int>(range[1] - 1), static_cast<int>(range[2] - 1)};
        const Index3 a_hi{static_cast<int>(range[3] - 1), static_cast<int>(range[4] - 1), static_cast<int>(range[5] - 1)};
        const Index3 b_lo = itf.map_node(a_lo), b_hi = itf.map_node(a_hi);
        for (int t = 0; t < 3; ++t) {
          donor[t] = b_lo[t] + 1;
          donor[t + 3] = b_hi[t] + 1;
        }
        if (itf.periodic) {
          // CGNS 1-to-1 periodic data needs a separate node; record the pair as a general BC.
          int bc = 0;
          check(cg_boco_write(fn, base, zone, fmt::format("{}_{}", p.label, nbc++).c_str(), BCGeneral, PointRange, 2,
                              range, &bc),
                "periodic patch");
          continue;
        }
        int transform[3];
        for (int m = 0; m < 3; ++m)
          for (int n = 0; n < 3; ++n)
            if (itf.T(n, m) != 0) transform[m] = itf.T(n, m) * (n + 1);
        int con = 0;
        check(cg_1to1_write(fn, base, zone, fmt::format("{}_{}", p.label, ncon++).c_str(), d.name.c_str(), range,
                            donor, transform, &con),
              "1-to-1 connection");
        continue;
      }
      int bc = 0;
      check(cg_boco_write(fn, base, zone, fmt::format("{}_{}", p.label, nbc++).c_str(), cgns_bc(p.type), PointRange,
                          2, range, &bc),
            "boundary condition " + p.label);
    }
  }
  check(cg_close(fn), "close");
  std::filesystem::rename(tmp, path);
}

}  // namespace narwhal
