#include "mesh/grid_quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.hpp"

namespace narwhal {
namespace {


void keep_min(QualityExtreme& e, Real v, const Block& b, int i, int j, int k) {
  if (v < e.value) e = {v, b.name, {i, j, k}};
}
void keep_max(QualityExtreme& e, Real v, const Block& b, int i, int j, int k) {
  if (v > e.value) e = {v, b.name, {i, j, k}};
}

Real scaled_corner_jacobian(const Block& b, int i, int j, int k) {
  Real worst = std::numeric_limits<Real>::infinity();
  for (int c = 0; c < 8; ++c) {
    const Index3 o{i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)};
    Vec3 e[3];
    for (int d = 0; d < 3; ++d) {
      const int step = o[d] == Index3{i, j, k}[d] ? 1 : -1;  // towards the cell's other corner
      Index3 n = o;
      n[d] += step;
      e[d] = step * (b.x(n[0], n[1], n[2]) - b.x(o[0], o[1], o[2]));
    }
    const Real scale = e[0].norm() * e[1].norm() * e[2].norm();
    const Real det = e[0].dot(e[1].cross(e[2]));
    worst = std::min(worst, scale > 0.0 ? det / scale : 0.0);
  }
  return worst;
}

// Width across direction d: volume over the mean area of the two faces normal to d.
Real cell_width(const Block& b, int d, int i, int j, int k) {
  const Index3 e = unit(d);
  const Real area = 0.5 * (b.S[d](i, j, k).norm() + b.S[d](i + e[0], j + e[1], k + e[2]).norm());
  return area > 0.0 ? b.vol(i, j, k) / area : 0.0;
}

bool is_wall(const Patch& p, const std::vector<std::string>& wall_labels) {
  return std::find(wall_labels.begin(), wall_labels.end(), p.label) != wall_labels.end();
}

// Calls f(face index, first cell, inward unit normal) for every face of a wall patch.
template <class F>
void for_each_wall_face(const Block& b, const Patch& p, F&& f) {
  const int d = side_dir(p.side);
  const bool high = side_high(p.side);
  const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
  for (int a = p.lo[t2]; a < p.hi[t2]; ++a)
    for (int c = p.lo[t1]; c < p.hi[t1]; ++c) {
      Index3 face{0, 0, 0};
      face[d] = high ? b.n(d) : 0;
      face[t1] = c;
      face[t2] = a;
      Index3 cell = face;
      if (high) cell[d] -= 1;
      const Vec3 S = b.S[d](face[0], face[1], face[2]);
      const Vec3 n = (high ? -1.0 : 1.0) * S.normalized();  // into the fluid
      f(face, cell, n);
    }
}

}  // namespace

Real flat_plate_friction_estimate(Real reynolds_length) { return 0.026 * std::pow(reynolds_length, -1.0 / 7.0); }

FoldReport measure_folds(const std::vector<Block>& blocks) {
  FoldReport r;
  r.worst.value = std::numeric_limits<Real>::infinity();
  for (const Block& b : blocks)
    for_each_cell(b, [&](int i, int j, int k) {
      const Real jac = scaled_corner_jacobian(b, i, j, k);
      keep_min(r.worst, jac, b, i, j, k);
      if (jac <= 0.0) ++r.folded;
    });
  return r;
}

GridQuality measure_grid_quality(const Grid& g, const std::vector<std::string>& wall_labels, Real reynolds) {
  constexpr Real inf = std::numeric_limits<Real>::infinity();
  GridQuality q;
  q.min_volume.value = inf;
  q.min_corner_jacobian.value = inf;
  q.min_wall_orthogonality_deg.value = inf;
  q.max_stretching.value = 1.0;
  q.max_aspect_ratio.value = 1.0;
  Real x_lo = inf, x_hi = -inf;
  for (const Block& b : g.blocks) {
    q.cells += b.cells();
    for_each_cell(b, [&](int i, int j, int k) {
      keep_min(q.min_volume, b.vol(i, j, k), b, i, j, k);
      const Real jac = scaled_corner_jacobian(b, i, j, k);
      keep_min(q.min_corner_jacobian, jac, b, i, j, k);
      if (jac <= 0.0) ++q.folded_cells;
      Real wmin = inf, wmax = 0.0;
      for (int d = 0; d < 3; ++d) {
        const Real w = cell_width(b, d, i, j, k);
        wmin = std::min(wmin, w);
        wmax = std::max(wmax, w);
        const Index3 e = unit(d);
        if (Index3{i, j, k}[d] + 1 < b.n(d)) {
          const Real w1 = cell_width(b, d, i + e[0], j + e[1], k + e[2]);
          if (w > 0.0 && w1 > 0.0) keep_max(q.max_stretching, std::max(w1 / w, w / w1), b, i, j, k);
        }
      }
      if (wmin > 0.0) keep_max(q.max_aspect_ratio, wmax / wmin, b, i, j, k);
    });
    for (const Patch& p : b.patches) {
      if (!is_wall(p, wall_labels)) continue;
      q.has_walls = true;
      const int d = side_dir(p.side);
      for_each_wall_face(b, p, [&](const Index3& face, const Index3& cell, const Vec3& n) {
        const Vec3 xf = b.xf[d](face[0], face[1], face[2]);
        Index3 opposite = face;
        opposite[d] += side_high(p.side) ? -1 : 1;
        const Vec3 line = b.xf[d](opposite[0], opposite[1], opposite[2]) - xf;
        const Real cosang = std::clamp(line.normalized().dot(n), -1.0, 1.0);
        keep_min(q.min_wall_orthogonality_deg, 90.0 - std::acos(cosang) * kDegreesPerRadian, b, cell[0], cell[1], cell[2]);
        const Real h = std::abs((b.xc(cell[0], cell[1], cell[2]) - xf).dot(n));
        keep_max(q.max_first_cell_height, h, b, cell[0], cell[1], cell[2]);
        const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
        for (int corner = 0; corner < 4; ++corner) {
          Index3 node = face;
          node[t1] += corner & 1;
          node[t2] += corner >> 1;
          x_lo = std::min(x_lo, b.x(node[0], node[1], node[2]).x());
          x_hi = std::max(x_hi, b.x(node[0], node[1], node[2]).x());
        }
      });
    }
  }
  if (q.has_walls && reynolds > 0.0) {
    const Real length = std::max(x_hi - x_lo, std::numeric_limits<Real>::min());
    const Real friction_velocity = std::sqrt(0.5 * flat_plate_friction_estimate(reynolds * length));
    q.max_y_plus = q.max_first_cell_height;
    q.max_y_plus.value *= reynolds * friction_velocity;
  }
  return q;
}

std::string format_grid_quality(const GridQuality& q) {
  auto at = [](const QualityExtreme& e) {
    return fmt::format("(block '{}', cell {}, {}, {})", e.block, e.cell[0], e.cell[1], e.cell[2]);
  };
  std::string s = fmt::format("  cells: {}\n", q.cells);
  s += fmt::format("  smallest cell volume:           {:.3e}  {}\n", q.min_volume.value, at(q.min_volume));
  s += fmt::format("  smallest scaled corner Jacobian: {:.3f}  {}  ({} folded or collapsed cell(s))\n",
                   q.min_corner_jacobian.value, at(q.min_corner_jacobian), q.folded_cells);
  if (q.has_walls) {
    s += fmt::format("  smallest wall orthogonality:    {:.2f} deg  {}\n", q.min_wall_orthogonality_deg.value,
                     at(q.min_wall_orthogonality_deg));
    s += fmt::format("  largest first-cell height:      {:.3e}  {}\n", q.max_first_cell_height.value,
                     at(q.max_first_cell_height));
    if (q.max_y_plus.value > 0.0)
      s += fmt::format("  largest y+ (estimate, Cf = 0.026 Re_L^-1/7): {:.2f}  {}\n", q.max_y_plus.value,
                       at(q.max_y_plus));
  } else {
    s += "  no wall patches\n";
  }
  s += fmt::format("  largest stretching ratio:       {:.3f}  {}\n", q.max_stretching.value, at(q.max_stretching));
  s += fmt::format("  largest aspect ratio:           {:.1f}  {}\n", q.max_aspect_ratio.value, at(q.max_aspect_ratio));
  return s;
}

void require_unfolded(const GridQuality& q, const std::string& where) {
  require_unfolded(FoldReport{q.min_corner_jacobian, q.folded_cells}, where);
}

void require_unfolded(const FoldReport& folds, const std::string& where) {
  if (folds.folded == 0) return;
  const QualityExtreme& e = folds.worst;
  fail("{}: the grid has {} folded or collapsed cell(s) (scaled corner Jacobian <= 0); the worst, {:.3f}, is in "
       "block '{}' cell ({}, {}, {})",
       where, folds.folded, e.value, e.block, e.cell[0], e.cell[1], e.cell[2]);
}

}  // namespace narwhal
