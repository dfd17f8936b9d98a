#include "io/openfoam_writer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"

namespace narwhal {
namespace {

using Quad = std::array<int, 4>;

struct Face {
  int owner = -1, neighbour = -1;
  Quad nodes{};
};

// One point per distinct node position: nodes on block boundaries are looked up in a
// hash of positions quantised to `tol` (the 27 neighbouring bins, so that two copies
// of a node on either side of a bin edge still meet).
class PointIndex {
 public:
  explicit PointIndex(Real tol) : tol_(tol) {}
  int interior(const Vec3& x) {
    points_.push_back(x);
    return static_cast<int>(points_.size()) - 1;
  }
  int shared(const Vec3& x) {
    const std::array<long long, 3> q{bin(x[0]), bin(x[1]), bin(x[2])};
    for (int a = -1; a <= 1; ++a)
      for (int b = -1; b <= 1; ++b)
        for (int c = -1; c <= 1; ++c) {
          const auto it = bins_.find(key({q[0] + a, q[1] + b, q[2] + c}));
          if (it == bins_.end()) continue;
          for (const int id : it->second)
            if ((points_[static_cast<std::size_t>(id)] - x).cwiseAbs().maxCoeff() <= tol_) return id;
        }
    const int id = interior(x);
    bins_[key(q)].push_back(id);
    return id;
  }
  const std::vector<Vec3>& points() const { return points_; }

 private:
  long long bin(Real v) const { return static_cast<long long>(std::floor(v / tol_)); }
  static std::size_t key(const std::array<long long, 3>& q) {
    std::size_t h = 1469598103934665603ull;
    for (const long long v : q) h = (h ^ static_cast<std::size_t>(v)) * 1099511628211ull;
    return h;
  }
  Real tol_;
  std::vector<Vec3> points_;
  std::unordered_map<std::size_t, std::vector<int>> bins_;
};

Real extent(const Grid& g) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const Block& b : g.blocks)
    for (int k = 0; k <= b.nk; ++k)
      for (int j = 0; j <= b.nj; ++j)
        for (int i = 0; i <= b.ni; ++i) {
          lo = lo.cwiseMin(b.x(i, j, k));
          hi = hi.cwiseMax(b.x(i, j, k));
        }
  return (hi - lo).maxCoeff();
}

// The four point ids of the face normal to d at node index `n`, ordered so that the
// right-hand normal points towards +d (blocks are right-handed).
Quad face_nodes(const std::vector<int>& ids, const Block& b, int d, const Index3& n) {
  const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
  auto id = [&](const Index3& m) {
    return ids[static_cast<std::size_t>(m[0] + (b.ni + 1) * (m[1] + (b.nj + 1) * static_cast<std::size_t>(m[2])))];
  };
  const Index3 a = n, c = add(n, unit(t1)), e = add(add(n, unit(t1)), unit(t2)), f = add(n, unit(t2));
  return {id(a), id(c), id(e), id(f)};
}

Quad reversed(const Quad& q) { return {q[0], q[3], q[2], q[1]}; }

void write_header(std::ostream& out, const std::string& cls, const std::string& object, const std::string& note = "") {
  out << "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class " << cls << ";\n";
  if (!note.empty()) out << "    note \"" << note << "\";\n";
  out << "    location \"constant/polyMesh\";\n    object " << object << ";\n}\n\n";
}

std::ofstream open_for_writing(const std::filesystem::path& p) {
  std::ofstream out(p);
  if (!out) fail("cannot write {}", p.string());
  out.precision(17);
  return out;
}

// Every node's point number, block by block, and where each block's cells start in the
// mesh's numbering.
struct NodeNumbering {
  std::vector<std::vector<int>> ids;
  std::vector<int> cell_offset;
};

NodeNumbering number_nodes(const Grid& g, PointIndex& index) {
  NodeNumbering nodes;
  nodes.ids.resize(g.blocks.size());
  nodes.cell_offset.assign(g.blocks.size() + 1, 0);
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    nodes.cell_offset[ib + 1] = nodes.cell_offset[ib] + static_cast<int>(b.cells());
    auto& ids = nodes.ids[ib];
    ids.reserve(static_cast<std::size_t>(b.ni + 1) * (b.nj + 1) * (b.nk + 1));
    for (int k = 0; k <= b.nk; ++k)
      for (int j = 0; j <= b.nj; ++j)
        for (int i = 0; i <= b.ni; ++i) {
          const bool on_side = i == 0 || j == 0 || k == 0 || i == b.ni || j == b.nj || k == b.nk;
          ids.push_back(on_side ? index.shared(b.x(i, j, k)) : index.interior(b.x(i, j, k)));
        }
  }
  return nodes;
}

// The mesh's faces: internal ones (owner < neighbour, sorted as OpenFOAM wants them) and
// boundary ones by patch label, the labels in order of first appearance.
struct MeshFaces {
  std::vector<Face> internal;
  std::vector<std::string> labels;
  std::map<std::string, std::vector<Face>> boundary;
  std::map<std::string, bool> is_wall;
};

MeshFaces collect_faces(const Grid& g, const NodeNumbering& nodes) {
  MeshFaces m;
  std::map<Quad, Face> unmatched;  // block-boundary faces off the patches, by sorted points
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    const auto& ids = nodes.ids[ib];
    // Cells block by block in the grid's block order, i fastest: the harness starts a peer run
    // from a Narwhal solution by this numbering (validation/harness/openfoam.py, seed_from_narwhal).
    auto cell = [&](const Index3& c) { return nodes.cell_offset[ib] + c[0] + b.ni * (c[1] + b.nj * c[2]); };
    for (int d = 0; d < 3; ++d) {
      // Faces inside the block: from the lower cell to the upper one.
      for (int k = 0; k < b.nk + (d == 2); ++k)
        for (int j = 0; j < b.nj + (d == 1); ++j)
          for (int i = 0; i < b.ni + (d == 0); ++i) {
            const Index3 n{i, j, k};
            if (n[d] == 0 || n[d] == b.n(d)) continue;
            m.internal.push_back({cell(add(n, unit(d), -1)), cell(n), face_nodes(ids, b, d, n)});
          }
    }
    // Block sides: patch faces, or faces to be joined to another block's.
    std::vector<std::vector<char>> covered(6);
    for (const Patch& p : b.patches) {
      if (p.type == BcType::Interface) continue;
      const int d = side_dir(p.side), t1 = (d + 1) % 3, t2 = (d + 2) % 3;
      if (std::find(m.labels.begin(), m.labels.end(), p.label) == m.labels.end()) m.labels.push_back(p.label);
      m.is_wall[p.label] = p.type == BcType::Wall;
      auto& faces = m.boundary[p.label];
      auto& cov = covered[static_cast<std::size_t>(p.side)];
      cov.resize(static_cast<std::size_t>(b.n(t1)) * b.n(t2), 0);
      for (int b2 = p.lo[t2]; b2 < p.hi[t2]; ++b2)
        for (int b1 = p.lo[t1]; b1 < p.hi[t1]; ++b1) {
          Index3 n{0, 0, 0};
          n[d] = side_high(p.side) ? b.n(d) : 0;
          n[t1] = b1;
          n[t2] = b2;
          Index3 c = n;
          if (side_high(p.side)) --c[d];
          const Quad q = face_nodes(ids, b, d, n);
          faces.push_back({cell(c), -1, side_high(p.side) ? q : reversed(q)});  // out of the domain
          cov[static_cast<std::size_t>(b1 + b.n(t1) * b2)] = 1;
        }
    }
    for (int side = 0; side < 6; ++side) {
      const int d = side_dir(side), t1 = (d + 1) % 3, t2 = (d + 2) % 3;
      auto& cov = covered[static_cast<std::size_t>(side)];
      cov.resize(static_cast<std::size_t>(b.n(t1)) * b.n(t2), 0);
      for (int b2 = 0; b2 < b.n(t2); ++b2)
        for (int b1 = 0; b1 < b.n(t1); ++b1) {
          if (cov[static_cast<std::size_t>(b1 + b.n(t1) * b2)]) continue;
          Index3 n{0, 0, 0};
          n[d] = side_high(side) ? b.n(d) : 0;
          n[t1] = b1;
          n[t2] = b2;
          Index3 c = n;
          if (side_high(side)) --c[d];
          const Quad q = face_nodes(ids, b, d, n);
          const Quad outward = side_high(side) ? q : reversed(q);
          Quad key = q;
          std::sort(key.begin(), key.end());
          const auto it = unmatched.find(key);
          if (it == unmatched.end()) {
            unmatched.emplace(key, Face{cell(c), -1, outward});
            continue;
          }
          const Face other = it->second;
          unmatched.erase(it);
          // From the lower-numbered cell, whose outward orientation is the face's.
          if (other.owner < cell(c))
            m.internal.push_back({other.owner, cell(c), other.nodes});
          else
            m.internal.push_back({cell(c), other.owner, outward});
        }
    }
  }
  if (!unmatched.empty())
    fail("OpenFOAM export: {} block-boundary face(s) have neither a patch nor a matching face of another block",
         unmatched.size());
  std::sort(m.internal.begin(), m.internal.end(), [](const Face& a, const Face& b) {
    return a.owner != b.owner ? a.owner < b.owner : a.neighbour < b.neighbour;
  });
  return m;
}

void write_points(const std::filesystem::path& dir, const PointIndex& index) {
  auto out = open_for_writing(dir / "points");
  write_header(out, "vectorField", "points");
  out << index.points().size() << "\n(\n";
  for (const Vec3& x : index.points()) out << '(' << x[0] << ' ' << x[1] << ' ' << x[2] << ")\n";
  out << ")\n";
}

// faces, owner and neighbour: the internal faces first, then each patch's.
void write_faces(const std::filesystem::path& dir, const MeshFaces& m, const OpenFoamMeshCounts& n) {
  const std::string note = fmt::format("nPoints:{}  nCells:{}  nFaces:{}  nInternalFaces:{}", n.points, n.cells,
                                       n.faces, n.internal_faces);
  auto faces = open_for_writing(dir / "faces");
  auto owner = open_for_writing(dir / "owner");
  auto neighbour = open_for_writing(dir / "neighbour");
  write_header(faces, "faceList", "faces");
  write_header(owner, "labelList", "owner", note);
  write_header(neighbour, "labelList", "neighbour", note);
  faces << n.faces << "\n(\n";
  owner << n.faces << "\n(\n";
  neighbour << n.internal_faces << "\n(\n";
  auto face = [&](const Face& f) {
    faces << "4(" << f.nodes[0] << ' ' << f.nodes[1] << ' ' << f.nodes[2] << ' ' << f.nodes[3] << ")\n";
    owner << f.owner << '\n';
  };
  for (const Face& f : m.internal) {
    face(f);
    neighbour << f.neighbour << '\n';
  }
  for (const std::string& label : m.labels)
    for (const Face& f : m.boundary.at(label)) face(f);
  faces << ")\n";
  owner << ")\n";
  neighbour << ")\n";
  if (!faces || !owner || !neighbour) fail("OpenFOAM export: writing {} failed", dir.string());
}

void write_boundary(const std::filesystem::path& dir, const MeshFaces& m, std::size_t internal_faces) {
  auto out = open_for_writing(dir / "boundary");
  write_header(out, "polyBoundaryMesh", "boundary");
  out << m.labels.size() << "\n(\n";
  std::size_t start = internal_faces;
  for (const std::string& label : m.labels) {
    const std::size_t count = m.boundary.at(label).size();
    out << "    " << label << "\n    {\n        type " << (m.is_wall.at(label) ? "wall" : "patch") << ";\n";
    if (m.is_wall.at(label)) out << "        inGroups 1(wall);\n";
    out << "        nFaces " << count << ";\n        startFace " << start << ";\n    }\n";
    start += count;
  }
  out << ")\n";
}

}  // namespace

OpenFoamMeshCounts write_openfoam_mesh(const std::string& case_dir, const Grid& g) {
  for (const Interface& f : g.interfaces)
    if (f.periodic) fail("OpenFOAM export: block '{}' has a periodic interface, which this export does not support",
                         g.blocks[static_cast<std::size_t>(f.block)].name);
  PointIndex index(1e-10 * std::max(extent(g), Real(1e-300)));
  const NodeNumbering nodes = number_nodes(g, index);
  const MeshFaces m = collect_faces(g, nodes);

  OpenFoamMeshCounts n;
  n.points = index.points().size();
  n.cells = static_cast<std::size_t>(nodes.cell_offset.back());
  n.internal_faces = m.internal.size();
  n.faces = m.internal.size();
  for (const auto& [label, faces] : m.boundary) n.faces += faces.size();

  const std::filesystem::path dir = std::filesystem::path(case_dir) / "constant" / "polyMesh";
  std::filesystem::create_directories(dir);
  write_points(dir, index);
  write_faces(dir, m, n);
  write_boundary(dir, m, n.internal_faces);
  return n;
}

}  // namespace narwhal
