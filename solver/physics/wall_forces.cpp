#include "physics/wall_forces.hpp"

#include <cmath>

#include "mesh/ghost_sweep.hpp"
#include "physics/residual.hpp"

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
      if (p.type != BcType::Wall) continue;
      auto& list = out[p.label];
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
        w.cp = 2.0 * q1[0];  // p_w = p_1 (§5.1), p_inf = 0
        Vec3 du = q1.tail<3>() - p.velocity;
        du -= w.n * w.n.dot(du);
        const Vec3 tau = du / (fp.reynolds * dw);  // §4.5
        w.cf = 2.0 * tau;
        w.y_plus = fp.reynolds * std::sqrt(tau.norm()) * dw;
        list.push_back(w);
      });
    }
  }
}

ForceCoefficients integrate_forces(const std::vector<WallFace>& faces, Real area_ref, Real length_ref,
                                   const Vec3& centre) {
  ForceCoefficients c;
  for (const auto& w : faces) {
    // Force of the fluid on the body: pressure pushes against n (n points into the fluid).
    const Vec3 dF = 0.5 * w.area * (-w.cp * w.n + w.cf);  // F = (-p n + tau) A in units of rho U^2 L^2
    c.force += dF;
    c.moment += (w.x - centre).cross(dF);
  }
  c.force *= 2.0 / area_ref;
  c.moment *= 2.0 / (area_ref * length_ref);
  return c;
}

}  // namespace narwhal
