#pragma once
// Monitor files the validation harness reads: history.csv (one row per
// iteration) and surface_<group>.csv (one row per wall face).
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "implicit/newton.hpp"
#include "physics/wall_forces.hpp"

namespace narwhal {

class HistoryWriter {
 public:
  // A new history.csv, or with `resume_after` (a run continuing from a restart written
  // at that iteration) the existing one cut back to its complete rows up to that
  // iteration — rows written after the checkpoint by a killed run, and a torn last
  // line, are dropped — so the continued history has each iteration once, in order.
  // `turbulence`: names of the turbulence model's variables (a residual column each).
  HistoryWriter(const std::string& path, const std::vector<std::string>& groups,
                const std::vector<std::string>& turbulence, std::optional<int> resume_after);
  ~HistoryWriter();
  HistoryWriter(const HistoryWriter&) = delete;
  HistoryWriter& operator=(const HistoryWriter&) = delete;
  // One row, written and flushed as a whole; a failed write is an Error naming the file.
  void write(int iteration, Real wall_seconds, const IterationNorms& n,
             const std::map<std::string, ForceCoefficients>& forces, const std::vector<Real>& turbulence = {});

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<std::string> groups_;
  std::size_t turbulence_ = 0;
};

// steps.csv of a dual-time run: one row per physical step (step, time t^{n+1}, the
// sub-iterations it took, the drop |R*| / |R*_0| they reached, each wall group's force
// and moment coefficients at the step's end).
class StepsWriter {
 public:
  // `resume_after`: a run continuing from the restart of that step keeps the rows up to it.
  StepsWriter(const std::string& path, const std::vector<std::string>& groups, std::optional<int> resume_after);
  ~StepsWriter();
  StepsWriter(const StepsWriter&) = delete;
  StepsWriter& operator=(const StepsWriter&) = delete;
  void write(int step, Real time, int subiterations, Real drop, const std::map<std::string, ForceCoefficients>& forces);

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<std::string> groups_;
};

// The first line of history.csv for these wall groups and turbulence variables.
std::string history_header(const std::vector<std::string>& groups, const std::vector<std::string>& turbulence);

// Written whole or not at all (io/text_file.hpp).
// cf_signed: |tau_w| with the sign of its x component, as NASA TMR reports Cf.
void write_surface_csv(const std::string& path, const std::vector<WallFace>& faces);

}  // namespace narwhal
