#pragma once
// Helpers shared by the solver tests: small grids, converged runs, CSV reading.
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bc/boundary.hpp"
#include "config/case_config.hpp"
#include "implicit/newton.hpp"
#include "mesh/appended_suboff.hpp"
#include "mesh/connectivity.hpp"
#include "mesh/generators.hpp"
#include "mesh/setup.hpp"
#include "physics/residual.hpp"

namespace narwhal::test {

// A new, empty directory of its own under the system temporary directory: two test
// runs at the same time never write into each other's paths.
inline std::filesystem::path fresh_temp_dir(const std::string& stem) {
  std::string pattern = (std::filesystem::temp_directory_path() / (stem + "_XXXXXX")).string();
  if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for " + pattern);
  return pattern;
}

inline std::string source_path(const std::string& rel) { return std::string(NARWHAL_SOURCE_DIR) + "/" + rel; }

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

// Columns of a CSV file with '#' comment lines and one header row (text cells read as NaN).
inline std::map<std::string, std::vector<double>> read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::string line;
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    if (names.empty()) {
      while (std::getline(ss, cell, ',')) names.push_back(cell);
      continue;
    }
    for (std::size_t c = 0; std::getline(ss, cell, ','); ++c) {
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      cols[names.at(c)].push_back(end != cell.c_str() ? v : std::nan(""));  // text columns: NaN
    }
  }
  return cols;
}

// Rows of a history.csv without the wall-clock column (2nd): everything else of a
// restarted run must match the uninterrupted one to the last digit.
inline std::vector<std::string> history_rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    const auto a = line.find(','), b = line.find(',', a + 1);
    rows.push_back(line.substr(0, a) + line.substr(b));
  }
  return rows;
}

// Largest distance between an interface's ghost node (one layer out, at tangential
// node `tangential`) and the donor node it copies; zero when connectivity is right.
inline Real interface_ghost_node_mismatch(const Grid& g, int tangential) {
  Real worst = 0.0;
  for (const auto& itf : g.interfaces) {
    const Block& a = g.blocks[itf.block];
    const Block& d = g.blocks[itf.donor];
    const int dir = side_dir(itf.side);
    Index3 node{tangential, tangential, tangential};
    node[dir] = side_high(itf.side) ? a.n(dir) + 1 : -1;
    worst = std::max(worst, (a.x(node) - d.x(itf.map_node(node))).norm());
  }
  return worst;
}

// The residual of the uniform state q0 (Dirichlet patches hold it) on a finalized
// grid: zero up to round-off when every cell closes (free-stream preservation).
inline std::vector<GhostArray<State>> uniform_state_residual(Grid& g, const State& q0) {
  FlowParams fp;
  fp.reynolds = 100.0;
  fp.exact = [q0](const Vec3&) { return q0; };
  FlowField f;
  f.allocate(g, fp, q0);
  fill_ghosts(g, f, fp);
  std::vector<GhostArray<State>> R;
  compute_residual(g, f, fp, R);
  return R;
}

// The residual of a uniform state, the worst cell, relative to the flux through the
// cell's faces (|R| / sum |S|, with |q| of order one): zero up to round-off when the
// cells close. Against the volume instead (|R|/V) the same round-off grows as the
// inverse of the wall spacing.
inline Real relative_free_stream_residual(Grid& g) {
  const std::vector<GhostArray<State>> R = uniform_state_residual(g, (State() << 0.3, 0.7, -0.2, 0.1).finished());
  Real worst = 0.0;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i) {
          Real faces = 0.0;
          for (int d = 0; d < 3; ++d) {
            Index3 hi{i, j, k};
            ++hi[d];
            faces += b.S[d](i, j, k).norm() + b.S[d](hi).norm();
          }
          worst = std::max(worst, R[ib](i, j, k).cwiseAbs().maxCoeff() / faces);
        }
  }
  return worst;
}

// Every node of every patch of a grid, with its block and patch.
template <class Visit>
void for_each_patch_node(const Grid& g, Visit&& visit) {
  for (const Block& b : g.blocks)
    for (const Patch& p : b.patches) {
      const int d = side_dir(p.side);
      for (int v = p.lo[(d + 2) % 3]; v <= p.hi[(d + 2) % 3]; ++v)
        for (int u = p.lo[(d + 1) % 3]; u <= p.hi[(d + 1) % 3]; ++u) {
          Index3 n{};
          n[d] = side_high(p.side) ? b.n(d) : 0;
          n[(d + 1) % 3] = u;
          n[(d + 2) % 3] = v;
          visit(b, p, b.x(n));
        }
    }
}

// The appended SUBOFF at 8 cells a stretch: every block of the production topology, small.
// The wall labels of the appended grid's appendages (mesh/appended_suboff.hpp), the hull's being "body".
inline const std::vector<std::string> kAppendageLabels{"sail", "upper_rudder", "lower_rudder",
                                                       "starboard_stern_plane", "port_stern_plane",
                                                       "starboard_sail_plane", "port_sail_plane"};

inline AppendedSuboffSpec small_appended_spec(const std::string& configuration) {
  AppendedSuboffSpec s;
  s.configuration = configuration;
  s.cells_bow = 8;
  s.cells_sail = 8;
  s.cells_middle = 8;
  s.cells_fin = 8;
  s.cells_stern = 8;
  s.cells_around = 8;
  s.cells_span = 8;
  s.cells_outer = 8;
  s.box_half_width = 2;
  s.cells_margin = 2;
  s.cells_section = 8;
  s.first_spacing = 1e-4;
  s.fin_spacing = 1e-4;
  s.tip_spacing = 1e-3;
  s.leading_edge_spacing = 2e-3;
  s.trailing_edge_spacing = 2e-3;
  s.pole_spacing = 1e-3;
  // The sail planes' tips need the sail's box wider than their span at their height (the
  // production grids' boxes are half a sector wide).
  if (configuration == "full") s.box_half_width = 4;
  return s;
}

// The case of small_appended_spec("stern4"): tests add keys with parse_case's overrides.
inline const char* kSmallAppendedCase = R"(
[grid]
type = "appended_suboff"
configuration = "stern4"
cells_bow = 8
cells_sail = 8
cells_middle = 8
cells_fin = 8
cells_stern = 8
cells_around = 8
cells_span = 8
cells_outer = 8
box_half_width = 2
cells_margin = 2
cells_section = 8
first_spacing = 1e-4
fin_spacing = 1e-4
tip_spacing = 1e-3
leading_edge_spacing = 2e-3
trailing_edge_spacing = 2e-3
pole_spacing = 1e-3
[flow]
reynolds = 1e6
[bc.body]
type = "wall"
[bc.farfield]
type = "farfield"
)";

// Iterate to a residual drop (or the iteration limit); returns the drop reached.
inline Real converge(NewtonSolver& s, Real drop, int max_it) {
  Real first = -1.0, last = 1.0;
  for (int it = 0; it < max_it; ++it) {
    const auto n = s.iterate();
    if (first < 0) first = n.total;
    last = n.total;
    if (last <= drop * first) break;
  }
  return last / first;
}

// A dual-time run's settings for tests: `steps` steps of `dt`.
inline TimeConfig time_config(TimeConfig::Scheme scheme, Real dt, int steps) {
  TimeConfig tc;
  tc.scheme = scheme;
  tc.step = dt;
  tc.steps = steps;
  return tc;
}

// One physical step's iterations (`iterate` returns the norms of the state entering
// it) until the residual has dropped `drop`, at most `most` of them.
template <class Iterate>
void converge_step(Iterate&& iterate, Real drop, int most) {
  Real first = -1.0;
  for (int m = 0; m < most; ++m) {
    const Real total = iterate().total;
    if (first < 0.0) first = total;
    if (total <= drop * first || total < 1e-15) break;
  }
}

}  // namespace narwhal::test
