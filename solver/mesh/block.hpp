#pragma once
// Structured block: nodes with two ghost layers, per-face-direction metrics
// (area vectors, face speeds), cell volumes and centres (NUMERICS §2), and the
// boundary patches that tile its six faces.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "fields/ghost_array.hpp"

namespace narwhal {

inline constexpr int kGhost = 2;  // MUSCL needs two ghost layers (§3.7).

// Size limits of one block. Ghost arrays address cells with int strides per row and
// 64-bit plane offsets; these keep every such product far from overflow, and lie well
// beyond what one block of a real grid needs (SUBOFF blocks have a few hundred cells
// per direction). A grid file or case asking for more is refused before allocating.
inline constexpr int kMaxCellsPerDirection = 1 << 16;
inline constexpr std::int64_t kMaxBlockCells = std::int64_t{1} << 28;
// Throws an Error naming `where` unless ci x cj x ck cells is a valid block size.
void check_block_size(const std::string& where, std::int64_t ci, std::int64_t cj, std::int64_t ck);

enum class BcType { Wall, Farfield, Inflow, Outflow, Symmetry, Dirichlet, Interface };

const char* to_string(BcType t);

// Side numbering: side = 2*dir + (high ? 1 : 0); dir 0,1,2 = i,j,k.
inline int side_dir(int side) { return side / 2; }
inline bool side_high(int side) { return side % 2 == 1; }
const char* side_name(int side);  // "imin", "imax", ...
int parse_side(const std::string& s);  // -1 when unknown

// A rectangle of boundary faces on one block side. `lo`/`hi` are half-open cell
// ranges in the two tangential directions (entries of the normal direction unused).
struct Patch {
  int side = 0;
  Index3 lo{0, 0, 0};
  Index3 hi{0, 0, 0};
  std::string label;           // grid-level name, e.g. "plate"; BCs are assigned by label
  BcType type = BcType::Interface;
  int interface = -1;          // index into Grid::interfaces when type == Interface
  // Physical data (filled from the case's [bc.<label>] table).
  Vec3 velocity = Vec3::Zero();  // wall velocity, inflow velocity or far-field velocity
  Real pressure = 0.0;           // outflow pressure
  // Part of the body: surface output and forces are taken here (every no-slip wall,
  // and slip walls: symmetry conditions on a body surface, for inviscid runs).
  bool body_surface = false;
};

// The velocity field of a grid in rigid motion at the current time level (NUMERICS §5.1:
// a wall moving with the grid has u_w = V + omega x (x_f - origin)). Fixed grids: none.
struct RigidVelocity {
  bool moving = false;
  Vec3 translation = Vec3::Zero();  // of the origin
  Vec3 angular = Vec3::Zero();
  Vec3 origin = Vec3::Zero();
  Vec3 at(const Vec3& x) const { return translation + angular.cross(x - origin); }
};

struct Block {
  std::string name;
  int ni = 0, nj = 0, nk = 0;  // cells

  GhostArray<Vec3> x;                  // nodes (ni+1)x(nj+1)x(nk+1), ghost nodes included
  std::array<GhostArray<Vec3>, 3> S;   // face area vectors per direction (§2.2)
  std::array<GhostArray<Vec3>, 3> xf;  // face centroids
  std::array<GhostArray<Real>, 3> kt;  // face speed term k_t = -v_g.S (§1.3); zero on fixed grids
  GhostArray<Real> vol;                // cell volumes (§2.3)
  GhostArray<Vec3> xc;                 // cell centres: mean of the 8 corner nodes (§2.1)
  std::vector<Patch> patches;
  RigidVelocity motion;  // set by a moving grid (motion/grid_motion.hpp)
  // Direction in which the block is a one-cell layer whose solution does not vary
  // (a planar slab between symmetry planes, or a layer periodic onto itself), or -1.
  // Set only by mark_invariant_directions (physics/invariant_direction.hpp); the
  // solver then skips those faces, whose fluxes cancel exactly.
  int invariant_dir = -1;
  // A piece cut by the load balancer (parallel/partition.hpp) remembers the block it
  // came from and where it starts there: files are written in the uncut layout, so
  // that a run on any number of ranks reads and writes the same files.
  std::string parent;           // empty: not a piece
  Index3 parent_offset{0, 0, 0};

  Block() = default;
  Block(std::string block_name, int ci, int cj, int ck);

  int n(int d) const { return d == 0 ? ni : (d == 1 ? nj : nk); }
  Index3 dims() const { return {ni, nj, nk}; }
  std::size_t cells() const { return static_cast<std::size_t>(ni) * nj * nk; }
};

// A 1-to-1 interface seen from the receiving block: ghost cells of `side` on
// `block` are copies of `donor` cells. Node map b = b0 + T (a - a0) (CGNS
// Transform generalised to a matrix); positions and velocities of the donor are
// mapped by x = R x_donor + t, u = R u_donor (identity for plain interfaces,
// a translation for periodic pairs, a rotation for rotational periodicity).
struct Interface {
  int block = -1, side = -1;
  int donor = -1, donor_side = -1;
  Eigen::Matrix3i T = Eigen::Matrix3i::Identity();
  Index3 a0{0, 0, 0}, b0{0, 0, 0};
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  bool periodic = false;

  Index3 map_node(const Index3& a) const;
  Index3 map_cell(const Index3& c) const;
};

struct HaloPlans;  // parallel/halo.hpp

struct Grid {
  std::vector<Block> blocks;
  std::vector<Interface> interfaces;
  // Distribution over MPI ranks (parallel/distribution.hpp): the rank owning each
  // block and this process's rank. Empty: every block is this process's. Solver
  // loops skip blocks they do not own; geometry is kept for every block.
  std::vector<int> owner;
  int rank = 0;
  // The halo exchange plans (parallel/halo.hpp), built on first use for this layout.
  mutable std::shared_ptr<const HaloPlans> halo;

  std::size_t cells() const;
  bool owns(int ib) const { return owner.empty() || owner[static_cast<std::size_t>(ib)] == rank; }
  bool owns(std::size_t ib) const { return owns(static_cast<int>(ib)); }
};

// Index unit vector of direction d.
inline Index3 unit(int d) {
  Index3 e{0, 0, 0};
  e[d] = 1;
  return e;
}

// a + s * b, componentwise (neighbour cells and faces).
inline Index3 add(Index3 a, const Index3& b, int s = 1) {
  for (int m = 0; m < 3; ++m) a[m] += s * b[m];
  return a;
}

// Calls f(i, j, k) for every interior cell in memory order (i fastest).
template <class F>
void for_each_cell(const Block& b, F&& f) {
  for (int k = 0; k < b.nk; ++k)
    for (int j = 0; j < b.nj; ++j)
      for (int i = 0; i < b.ni; ++i) f(i, j, k);
}

// The same forward (memory order) or backward: the two halves of a symmetric
// Gauss-Seidel sweep.
template <class F>
void for_each_cell_ordered(const Block& b, bool forward, F&& f) {
  if (forward) {
    for_each_cell(b, f);
    return;
  }
  for (int k = b.nk - 1; k >= 0; --k)
    for (int j = b.nj - 1; j >= 0; --j)
      for (int i = b.ni - 1; i >= 0; --i) f(i, j, k);
}

// Recompute S, face centroids, volumes and centres over the whole ghost-extended
// range (§2.2–2.3). Ghost nodes must be filled first.
// Bounding box [xmin, ymin, zmin, xmax, ymax, zmax] of a block's own nodes (ghost nodes
// left out) at positions `nodes` (the block's, or a copy in its layout).
std::array<double, 6> node_extent(const Block& b, const GhostArray<Vec3>& nodes);
inline std::array<double, 6> node_extent(const Block& b) { return node_extent(b, b.x); }

void compute_metrics(Block& b);

// Ghost nodes: linear extrapolation at physical boundaries (§2.1), donor copies
// at interfaces. Fills face, edge and corner ghosts.
void fill_ghost_nodes(Grid& g);

// Full geometric preparation: ghost nodes then metrics of every block.
void prepare_geometry(Grid& g);

// One array of `value` per cell of each block this rank owns (no ghost layers; other
// ranks' blocks: empty): per-cell data a solver keeps beside the flow field.
template <class T>
std::vector<GhostArray<T>> owned_cell_arrays(const Grid& g, const T& value) {
  std::vector<GhostArray<T>> out(g.blocks.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    if (g.owns(ib)) out[ib].resize(g.blocks[ib].ni, g.blocks[ib].nj, g.blocks[ib].nk, 0, value);
  return out;
}

}  // namespace narwhal
