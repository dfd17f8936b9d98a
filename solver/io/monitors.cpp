#include "io/monitors.hpp"

#include <filesystem>

#include <fmt/format.h>

#include "core/error.hpp"
#include "version.hpp"

namespace narwhal {

HistoryWriter::HistoryWriter(const std::string& path, const std::vector<std::string>& groups, bool append,
                             const std::vector<std::string>& turbulence)
    : groups_(groups), turbulence_(turbulence.size()) {
  const bool existed = append && std::filesystem::exists(path);
  file_ = std::fopen(path.c_str(), existed ? "a" : "w");
  if (!file_) fail("cannot write '{}'", path);
  if (!existed) {
    fmt::print(file_, "iteration,wall_s,cfl,res_p,res_u,res_v,res_w");
    for (const auto& t : turbulence) fmt::print(file_, ",res_{}", t);
    for (const auto& g : groups_)
      for (const char* c : {"cfx", "cfy", "cfz", "cmx", "cmy", "cmz"}) fmt::print(file_, ",{}_{}", g, c);
    fmt::print(file_, "\n");
  }
}

HistoryWriter::~HistoryWriter() {
  if (file_) std::fclose(file_);
}

void HistoryWriter::write(int iteration, Real wall_seconds, const IterationNorms& n,
                          const std::map<std::string, ForceCoefficients>& forces, const std::vector<Real>& turbulence) {
  // Full precision: restart equality compares these rows.
  fmt::print(file_, "{},{:.6f},{:.6e},{:.17g},{:.17g},{:.17g},{:.17g}", iteration, wall_seconds, n.cfl, n.l2[0],
             n.l2[1], n.l2[2], n.l2[3]);
  for (std::size_t m = 0; m < turbulence_; ++m) fmt::print(file_, ",{:.17g}", m < turbulence.size() ? turbulence[m] : 0.0);
  for (const auto& g : groups_) {
    const auto& c = forces.at(g);
    fmt::print(file_, ",{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}", c.force[0], c.force[1], c.force[2],
               c.moment[0], c.moment[1], c.moment[2]);
  }
  fmt::print(file_, "\n");
}

void HistoryWriter::flush() { std::fflush(file_); }

void write_surface_csv(const std::string& path, const std::vector<WallFace>& faces) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) fail("cannot write '{}'", path);
  fmt::print(f, "# narwhal {} ({}); one row per wall face; n points into the fluid; cp = 2p, cf = 2 tau_w\n",
             kVersion, kGitSha);
  fmt::print(f, "x,y,z,nx,ny,nz,area,cp,cf_x,cf_y,cf_z,y_plus\n");
  for (const auto& w : faces)
    fmt::print(f, "{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.6e}\n",
               w.x[0], w.x[1], w.x[2], w.n[0], w.n[1], w.n[2], w.area, w.cp, w.cf[0], w.cf[1], w.cf[2], w.y_plus);
  std::fclose(f);
}

}  // namespace narwhal
