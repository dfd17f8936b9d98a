#include "physics/wall_forces.hpp"

#include <cmath>

#include "bc/boundary.hpp"
#include "mesh/ghost_sweep.hpp"
#include "physics/residual.hpp"
#include "parallel/reduction.hpp"

namespace narwhal {

std::map<std::string, std::vector<WallFace>> wall_faces(const Grid& g, const FlowField& f, const FlowParams& fp) {
  std::map<std::string, std::vector<WallFace>> out;
  wall_faces(g, f, fp, out);
  return out;
}

void wall_faces(const Grid& g, const FlowField& f, const FlowParams& fp,
                std::map<std::string, std::vector<WallFace>>& out) {
  for (auto& [name, list] : out) list.clear();  // keeps capacity
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    for (const Patch& p : b.patches) {
      if (!p.body_surface) continue;
      auto& list = out[p.label];  // every rank knows every group, faces or not
      if (!g.owns(ib)) continue;
      const int d = side_dir(p.side);
      const PatchRange r = face_range(p);
      for_each_in(r, [&](Index3 c) {
        WallFace w;
        const Real dw = wall_distance(b, p.side, c, &w.n);
        Index3 fidx = c;
        fidx[d] = side_high(p.side) ? b.n(d) : 0;
        const State& q1 = f.Q[ib](interior_cell(b, p.side, c, 1));
        w.x = b.xf[d](fidx);
        w.area = b.S[d](fidx).norm();
        w.cp = 2.0 * q1[0];  // p_w = p_1 (§5.1, §5.4), p_inf = 0
        if (p.type != BcType::Wall) {  // a slip wall carries no shear
          list.push_back(w);
          return;
        }
        Vec3 du = q1.tail<3>() - wall_velocity(b, p, fidx);
        du -= w.n * w.n.dot(du);
        const Vec3 tau = du / (fp.reynolds * dw);  // §4.5
        w.cf = 2.0 * tau;
        w.y_plus = fp.reynolds * std::sqrt(tau.norm()) * dw;
        list.push_back(w);
      });
    }
  }
}

ForceCoefficients integrate_forces(std::span<const WallFace> faces, Real area_ref, Real length_ref,
                                   const Vec3& centre) {
  ForceCoefficients c;
  for (const auto& w : faces) {
    // Force of the fluid on the body: pressure pushes against n (n points into the fluid).
    const Vec3 dP = -0.5 * w.area * w.cp * w.n;  // F = (-p n + tau) A in units of rho U^2 L^2
    const Vec3 dF = dP + 0.5 * w.area * w.cf;
    c.force += dF;
    c.moment += (w.x - centre).cross(dF);
    c.pressure_force += dP;
    c.pressure_moment += (w.x - centre).cross(dP);
  }
  const Real to_force = 2.0 / area_ref, to_moment = 2.0 / (area_ref * length_ref);
  c.force *= to_force;
  c.pressure_force *= to_force;
  c.moment *= to_moment;
  c.pressure_moment *= to_moment;
  return c;
}

std::map<std::string, ForceCoefficients> integrate_forces(const Communicator& comm, const Grid& g,
                                                          const std::map<std::string, std::vector<WallFace>>& faces,
                                                          Real area_ref, Real length_ref, const Vec3& centre) {
  // Per (group, block) partial forces, added in block order on every rank: the same
  // sums for any distribution of the blocks. The face lists hold the owned blocks'
  // faces in block order; walk them alongside the patches.
  constexpr int width = 12;  // force, moment, pressure force, pressure moment
  const std::size_t groups = faces.size();
  std::vector<Real> partial(g.blocks.size() * groups * width, 0.0);
  std::size_t gi = 0;
  for (const auto& [name, list] : faces) {
    std::size_t next = 0;
    for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
      if (!g.owns(ib)) continue;
      const Block& b = g.blocks[ib];
      std::size_t n = 0;
      for (const Patch& p : b.patches)
        if (p.body_surface && p.label == name) {
          const PatchRange r = face_range(p);
          n += static_cast<std::size_t>(r.hi[0] - r.lo[0]) * (r.hi[1] - r.lo[1]) * (r.hi[2] - r.lo[2]);
        }
      const ForceCoefficients c = integrate_forces(std::span<const WallFace>(list).subspan(next, n), area_ref,
                                                   length_ref, centre);
      next += n;
      Real* s = &partial[(ib * groups + gi) * width];
      for (int m = 0; m < 3; ++m) {
        s[m] = c.force[m];
        s[3 + m] = c.moment[m];
        s[6 + m] = c.pressure_force[m];
        s[9 + m] = c.pressure_moment[m];
      }
    }
    ++gi;
  }
  // Totals per group: sum_in_block_order over blocks of width groups*6.
  const std::vector<Real> total = sum_in_block_order(comm, g, std::move(partial), static_cast<int>(groups * width));
  std::map<std::string, ForceCoefficients> out;
  gi = 0;
  for (const auto& [name, list] : faces) {
    ForceCoefficients& c = out[name];
    const Real* t = &total[gi * width];
    for (int m = 0; m < 3; ++m) {
      c.force[m] = t[m];
      c.moment[m] = t[3 + m];
      c.pressure_force[m] = t[6 + m];
      c.pressure_moment[m] = t[9 + m];
    }
    ++gi;
  }
  return out;
}

}  // namespace narwhal
