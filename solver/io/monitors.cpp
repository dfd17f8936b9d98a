#include "io/monitors.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/text_file.hpp"
#include "version.hpp"

namespace narwhal {

namespace {

// Each wall group's force and moment coefficients: the header's and a row's columns.
std::string force_header(const std::vector<std::string>& groups) {
  std::string h;
  for (const auto& g : groups)
    for (const char* c : {"cfx", "cfy", "cfz", "cmx", "cmy", "cmz"}) h += fmt::format(",{}_{}", g, c);
  return h;
}

std::string force_fields(const std::vector<std::string>& groups, const std::map<std::string, ForceCoefficients>& forces) {
  std::string row;
  for (const auto& g : groups) {
    const auto& c = forces.at(g);
    row += fmt::format(",{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}", c.force[0], c.force[1], c.force[2],
                       c.moment[0], c.moment[1], c.moment[2]);
  }
  return row;
}

// The rows of an existing file that a run resuming after `iteration` keeps.
std::string rows_kept(const std::string& path, const std::string& header, int iteration) {
  const std::string text = read_text_file(path);
  if (text.compare(0, header.size(), header) != 0)
    fail("cannot continue '{}': its columns are not this run's (another case or turbulence model wrote it)", path);
  const auto fields = std::count(header.begin(), header.end(), ',') + 1;
  std::string kept = header;
  int last = 0;
  std::size_t at = header.size();
  for (std::size_t end; (end = text.find('\n', at)) != std::string::npos; at = end + 1) {
    const std::string line = text.substr(at, end - at);
    const int it = std::atoi(line.c_str());
    // Complete rows only: a row cut by a kill has fewer fields.
    if (std::count(line.begin(), line.end(), ',') + 1 != fields || it <= last || it > iteration) continue;
    kept += line + "\n";
    last = it;
  }
  return kept;
}

}  // namespace

std::string history_header(const std::vector<std::string>& groups, const std::vector<std::string>& turbulence) {
  std::string h = "iteration,wall_s,cfl,res_p,res_u,res_v,res_w";
  for (const auto& t : turbulence) h += ",res_" + t;
  return h + force_header(groups) + "\n";
}

AppendedCsv::AppendedCsv(const std::string& path, const std::string& header, std::optional<int> resume_after)
    : path_(path) {
  const bool resume = resume_after && std::filesystem::exists(path);
  write_file_atomically(path, resume ? rows_kept(path, header, *resume_after) : header);
  file_ = std::fopen(path.c_str(), "a");
  if (!file_) fail("cannot write '{}': {}", path, std::strerror(errno));
}

AppendedCsv::~AppendedCsv() {
  if (file_) std::fclose(file_);
}

void AppendedCsv::append(const std::string& row) {
  if (std::fwrite(row.data(), 1, row.size(), file_) != row.size() || std::fflush(file_) != 0)
    fail("cannot write '{}': {}", path_, std::strerror(errno));
}

HistoryWriter::HistoryWriter(const std::string& path, const std::vector<std::string>& groups,
                             const std::vector<std::string>& turbulence, std::optional<int> resume_after)
    : groups_(groups), turbulence_(turbulence.size()), file_(path, history_header(groups, turbulence), resume_after) {}

void HistoryWriter::write(int iteration, Real wall_seconds, const IterationNorms& n,
                          const std::map<std::string, ForceCoefficients>& forces, const std::vector<Real>& turbulence) {
  // Full precision: restart equality compares these rows.
  std::string row = fmt::format("{},{:.6f},{:.6e},{:.17g},{:.17g},{:.17g},{:.17g}", iteration, wall_seconds, n.cfl,
                                n.l2[0], n.l2[1], n.l2[2], n.l2[3]);
  for (std::size_t m = 0; m < turbulence_; ++m) row += fmt::format(",{:.17g}", m < turbulence.size() ? turbulence[m] : 0.0);
  file_.append(row + force_fields(groups_, forces) + "\n");
}

PropulsorWriter::PropulsorWriter(const std::string& path, std::optional<int> resume_after)
    : file_(path, "iteration,rps,advance_speed,advance_ratio,thrust,torque,resistance\n", resume_after) {}

void PropulsorWriter::write(int iteration, Real rps, Real advance_speed, Real advance_ratio, Real thrust, Real torque,
                            Real resistance) {
  file_.append(fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", iteration, rps, advance_speed,
                           advance_ratio, thrust, torque, resistance));
}

ControlsWriter::ControlsWriter(const std::string& path, std::optional<int> resume_after)
    : file_(path, "step,time,rudder_deg,stern_planes_deg,sail_planes_deg,pitch_command_deg\n", resume_after) {}

void ControlsWriter::write(int step, Real time, Real rudder, Real stern_planes, Real sail_planes, Real pitch_command) {
  const auto degrees = [](Real radians) { return radians * kDegreesPerRadian + 0.0; };  // + 0.0: no "-0"
  file_.append(fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", step, time, degrees(rudder),
                           degrees(stern_planes), degrees(sail_planes), degrees(pitch_command)));
}

StepsWriter::StepsWriter(const std::string& path, const std::vector<std::string>& groups,
                         std::optional<int> resume_after)
    : groups_(groups), file_(path, "step,time,subiterations,drop" + force_header(groups) + "\n", resume_after) {}

void StepsWriter::write(int step, Real time, int subiterations, Real drop,
                        const std::map<std::string, ForceCoefficients>& forces) {
  file_.append(fmt::format("{},{:.17g},{},{:.6e}", step, time, subiterations, drop) + force_fields(groups_, forces) +
               "\n");
}

MotionWriter::MotionWriter(const std::string& path, std::optional<int> resume_after)
    : file_(path,
            "step,time,x,y,z,e0,e1,e2,e3,roll_deg,pitch_deg,yaw_deg,u,v,w,p,q,r,X,Y,Z,K,M,N,subiterations,"
            "coupling_change\n",
            resume_after) {}

void MotionWriter::write(int step, Real time, const RigidBodyState& s, const EulerAngles& turned, const BodyLoads& flow,
                         int subiterations, Real coupling_change) {
  std::string row = fmt::format("{},{:.17g}", step, time);
  for (int m = 0; m < 3; ++m) row += fmt::format(",{:.12e}", s.position()[m]);
  for (int m = 0; m < 4; ++m) row += fmt::format(",{:.12e}", s.attitude()[m]);
  for (Real angle : {turned.roll, turned.pitch, turned.yaw}) row += fmt::format(",{:.9e}", angle * kDegreesPerRadian);
  for (int m = 0; m < 6; ++m) row += fmt::format(",{:.12e}", s.y[m]);
  for (int m = 0; m < 3; ++m) row += fmt::format(",{:.9e}", flow.force[m]);
  for (int m = 0; m < 3; ++m) row += fmt::format(",{:.9e}", flow.moment[m]);
  file_.append(row + fmt::format(",{},{:.3e}\n", subiterations, coupling_change));
}

void write_surface_csv(const std::string& path, const std::vector<WallFace>& faces) {
  std::string out = fmt::format(
      "# narwhal {} ({}); one row per wall face; n points into the fluid; cp = 2p, cf = 2 tau_w; "
      "cf_signed = |cf| with the sign of cf_x\n",
      kVersion, kGitSha);
  out += "x,y,z,nx,ny,nz,area,cp,cf_x,cf_y,cf_z,cf_signed,y_plus\n";
  for (const auto& w : faces) {
    const Real cf_signed = std::copysign(w.cf.norm(), w.cf[0]);
    out += fmt::format("{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},"
                       "{:.6e}\n",
                       w.x[0], w.x[1], w.x[2], w.n[0], w.n[1], w.n[2], w.area, w.cp, w.cf[0], w.cf[1], w.cf[2],
                       cf_signed, w.y_plus);
  }
  write_file_atomically(path, out);
}

}  // namespace narwhal
