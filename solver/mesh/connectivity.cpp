#include "mesh/connectivity.hpp"

#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace narwhal {
namespace {

Real face_min_edge(const Block& b, int side) {
  const int d = side_dir(side);
  const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
  Real h = std::numeric_limits<Real>::max();
  Index3 a{0, 0, 0};
  a[d] = side_high(side) ? b.n(d) : 0;
  for (int q = 0; q <= b.n(t2); ++q)
    for (int p = 0; p <= b.n(t1); ++p) {
      a[t1] = p;
      a[t2] = q;
      Index3 e1 = a, e2 = a;
      e1[t1] += 1;
      e2[t2] += 1;
      if (p < b.n(t1)) h = std::min(h, (b.x(e1) - b.x(a)).norm());
      if (q < b.n(t2)) h = std::min(h, (b.x(e2) - b.x(a)).norm());
    }
  return h;
}

// Mean of the patch's face nodes: for faces that match node-to-node under a
// translation, the difference of these means is exactly that translation.
Vec3 face_node_mean(const Block& b, const Patch& p) {
  const int d = side_dir(p.side);
  Vec3 c = Vec3::Zero();
  int n = 0;
  Index3 lo = p.lo, hi = p.hi;
  lo[d] = hi[d] = side_high(p.side) ? b.n(d) : 0;
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        c += b.x(i, j, k);
        ++n;
      }
  return c / n;
}

bool is_full_face(const Block& b, const Patch& p) {
  const int d = side_dir(p.side);
  for (int t = 0; t < 3; ++t)
    if (t != d && (p.lo[t] != 0 || p.hi[t] != b.n(t))) return false;
  return true;
}

Patch full_face_patch(const Block& b, int side) {
  Patch p;
  p.side = side;
  p.lo = {0, 0, 0};
  p.hi = b.dims();
  return p;
}

// Whether the two faces have the same node counts, in one order or the other.
bool same_face_shape(const Block& A, int sa, const Block& B, int sb) {
  const int dA = side_dir(sa), dB = side_dir(sb);
  const int a1 = A.n((dA + 1) % 3), a2 = A.n((dA + 2) % 3);
  const int b1 = B.n((dB + 1) % 3), b2 = B.n((dB + 2) % 3);
  return (a1 == b1 && a2 == b2) || (a1 == b2 && a2 == b1);
}

// match_faces with its tolerance given: the faces' nodes agree to within `tol`.
std::optional<Interface> match_faces_within(const Grid& g, int ba, int sa, int bb, int sb, const Mat3& R,
                                            const Vec3& t, Real tol) {
  const Block& A = g.blocks[ba];
  const Block& B = g.blocks[bb];
  const int dA = side_dir(sa), dB = side_dir(sb);
  const int a1 = (dA + 1) % 3, a2 = (dA + 2) % 3;
  const int u1 = (dB + 1) % 3, u2 = (dB + 2) % 3;
  const int sgnN = (side_high(sa) ? 1 : -1) * (side_high(sb) ? -1 : 1);

  for (int swap = 0; swap < 2; ++swap) {
    const int m1 = swap ? u2 : u1;  // B direction that A's a1 runs along
    const int m2 = swap ? u1 : u2;
    if (A.n(a1) != B.n(m1) || A.n(a2) != B.n(m2)) continue;
    for (int s1 = -1; s1 <= 1; s1 += 2)
      for (int s2 = -1; s2 <= 1; s2 += 2) {
        Interface itf;
        itf.block = ba;
        itf.side = sa;
        itf.donor = bb;
        itf.donor_side = sb;
        itf.T.setZero();
        itf.T(dB, dA) = sgnN;
        itf.T(m1, a1) = s1;
        itf.T(m2, a2) = s2;
        itf.a0 = {0, 0, 0};
        itf.a0[dA] = side_high(sa) ? A.n(dA) : 0;
        itf.b0[dB] = side_high(sb) ? B.n(dB) : 0;
        itf.b0[m1] = s1 > 0 ? 0 : B.n(m1);
        itf.b0[m2] = s2 > 0 ? 0 : B.n(m2);
        itf.R = R;
        itf.t = t;
        bool ok = true;
        Index3 a = itf.a0;
        for (int q = 0; q <= A.n(a2) && ok; ++q)
          for (int p = 0; p <= A.n(a1) && ok; ++p) {
            a[a1] = p;
            a[a2] = q;
            const Vec3 xb = R * B.x(itf.map_node(a)) + t;
            if ((A.x(a) - xb).norm() > tol) ok = false;
          }
        if (ok) return itf;
      }
  }
  return std::nullopt;
}

}  // namespace

std::optional<Interface> match_faces(const Grid& g, int ba, int sa, int bb, int sb, const Mat3& R,
                                     const Vec3& t) {
  if (!same_face_shape(g.blocks[ba], sa, g.blocks[bb], sb)) return std::nullopt;
  const Real tol = 1e-6 * std::min(face_min_edge(g.blocks[ba], sa), face_min_edge(g.blocks[bb], sb));
  return match_faces_within(g, ba, sa, bb, sb, R, t, tol);
}

void connect_free_faces(Grid& g) {
  struct Free {
    int block, side;
    bool taken = false;
  };
  std::vector<Free> free;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for (int s = 0; s < 6; ++s) {
      bool covered = false;
      for (const auto& p : g.blocks[ib].patches)
        if (p.side == s) covered = true;
      if (!covered) free.push_back({static_cast<int>(ib), s});
    }
  // Each face's shortest edge once, not once per pair tried: the pairs are quadratic in
  // the free faces (a grid of some 200 blocks: 10^5 pairs), and the edges took most of the
  // appended grid's build, which a manoeuvre repeats whenever a surface turns.
  std::vector<Real> shortest(free.size());
  for (std::size_t f = 0; f < free.size(); ++f) shortest[f] = face_min_edge(g.blocks[free[f].block], free[f].side);
  for (std::size_t f = 0; f < free.size(); ++f) {
    if (free[f].taken) continue;
    bool found = false;
    for (std::size_t h = f + 1; h < free.size() && !found; ++h) {
      if (free[h].taken) continue;
      const Block& A = g.blocks[free[f].block];
      if (!same_face_shape(A, free[f].side, g.blocks[free[h].block], free[h].side)) continue;
      const Real tol = 1e-6 * std::min(shortest[f], shortest[h]);
      auto ab = match_faces_within(g, free[f].block, free[f].side, free[h].block, free[h].side, Mat3::Identity(),
                                   Vec3::Zero(), tol);
      if (!ab) continue;
      auto ba = match_faces_within(g, free[h].block, free[h].side, free[f].block, free[f].side, Mat3::Identity(),
                                   Vec3::Zero(), tol);
      if (!ba) continue;
      for (auto* itf : {&*ab, &*ba}) {
        Block& blk = g.blocks[itf->block];
        Patch p = full_face_patch(blk, itf->side);
        p.label = fmt::format("interface:{}", g.blocks[itf->donor].name);
        p.type = BcType::Interface;
        p.interface = static_cast<int>(g.interfaces.size());
        g.interfaces.push_back(*itf);
        blk.patches.push_back(p);
      }
      free[f].taken = free[h].taken = true;
      found = true;
    }
    if (!found)
      fail("block '{}' side {} has no boundary patch and matches no other block face point-to-point",
           g.blocks[free[f].block].name, side_name(free[f].side));
  }
}

void connect_periodic(Grid& g, const std::string& label_a, const std::string& label_b, const Mat3& R,
                      const std::optional<Vec3>& t_given) {
  // Every patch of each label (a face cut into pieces, e.g. by the load balancer,
  // carries its label on every piece); each must be a whole block face.
  auto find = [&](const std::string& label) {
    std::vector<std::pair<int, int>> out;
    for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
      for (std::size_t ip = 0; ip < g.blocks[ib].patches.size(); ++ip)
        if (g.blocks[ib].patches[ip].label == label) {
          if (!is_full_face(g.blocks[ib], g.blocks[ib].patches[ip]))
            fail("periodic boundary '{}' must cover whole block faces (block '{}' side {})", label,
                 g.blocks[ib].name, side_name(g.blocks[ib].patches[ip].side));
          out.emplace_back(static_cast<int>(ib), static_cast<int>(ip));
        }
    if (out.empty()) fail("periodic boundary: no patch labelled '{}'", label);
    return out;
  };
  const auto as = find(label_a);
  const auto bs = find(label_b);
  if (as.size() != bs.size())
    fail("periodic pair '{}' / '{}': {} faces against {}", label_a, label_b, as.size(), bs.size());
  // The translation from the face centres: the pieces pair up one to one, so the means
  // of their centres map onto each other as the whole faces do.
  Vec3 ma = Vec3::Zero(), mb = Vec3::Zero();
  for (const auto& [ib, ip] : as) ma += face_node_mean(g.blocks[ib], g.blocks[ib].patches[ip]);
  for (const auto& [ib, ip] : bs) mb += face_node_mean(g.blocks[ib], g.blocks[ib].patches[ip]);
  const Vec3 t = t_given ? *t_given : Vec3((ma - R * mb) / static_cast<Real>(as.size()));
  std::vector<bool> used(bs.size(), false);
  for (const auto& [ia, pa] : as) {
    bool joined = false;
    for (std::size_t k = 0; k < bs.size() && !joined; ++k) {
      if (used[k]) continue;
      const auto [ib, pb] = bs[k];
      Patch& PA = g.blocks[ia].patches[pa];
      Patch& PB = g.blocks[ib].patches[pb];
      auto ab = match_faces(g, ia, PA.side, ib, PB.side, R, t);
      if (!ab) continue;
      auto ba = match_faces(g, ib, PB.side, ia, PA.side, R.transpose(), -R.transpose() * t);
      if (!ba) continue;
      ab->periodic = ba->periodic = true;
      PA.type = PB.type = BcType::Interface;
      PA.interface = static_cast<int>(g.interfaces.size());
      g.interfaces.push_back(*ab);
      PB.interface = static_cast<int>(g.interfaces.size());
      g.interfaces.push_back(*ba);
      used[k] = joined = true;
    }
    if (!joined)
      fail("periodic pair '{}' / '{}': the faces do not match node-to-node under the given transform", label_a,
           label_b);
  }
}

void check_patch_cover(const Grid& g) {
  for (const auto& b : g.blocks)
    for (int s = 0; s < 6; ++s) {
      const int d = side_dir(s);
      const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
      std::vector<int> count(static_cast<std::size_t>(b.n(t1)) * b.n(t2), 0);
      for (const auto& p : b.patches) {
        if (p.side != s) continue;
        if (p.lo[t1] < 0 || p.hi[t1] > b.n(t1) || p.lo[t2] < 0 || p.hi[t2] > b.n(t2) || p.lo[t1] >= p.hi[t1] ||
            p.lo[t2] >= p.hi[t2])
          fail("block '{}' side {}: patch '{}' has an empty or out-of-range index range", b.name, side_name(s),
               p.label);
        for (int q = p.lo[t2]; q < p.hi[t2]; ++q)
          for (int r = p.lo[t1]; r < p.hi[t1]; ++r) count[static_cast<std::size_t>(q) * b.n(t1) + r]++;
      }
      for (int q = 0; q < b.n(t2); ++q)
        for (int r = 0; r < b.n(t1); ++r) {
          const int c = count[static_cast<std::size_t>(q) * b.n(t1) + r];
          if (c != 1)
            fail("block '{}' side {}: face cell ({}, {}) is covered by {} patches (expected exactly 1)", b.name,
                 side_name(s), r, q, c);
        }
    }
}

}  // namespace narwhal
