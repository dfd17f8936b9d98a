#pragma once
// Monitor files the validation harness reads: history.csv (one row per
// iteration) and surface_<group>.csv (one row per wall face).
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "implicit/newton.hpp"
#include "physics/wall_forces.hpp"

namespace narwhal {

class HistoryWriter {
 public:
  // Appends to an existing file when `append` (restarted runs keep one history).
  // `turbulence`: names of the turbulence model's variables (a residual column each).
  HistoryWriter(const std::string& path, const std::vector<std::string>& groups, bool append,
                const std::vector<std::string>& turbulence = {});
  ~HistoryWriter();
  HistoryWriter(const HistoryWriter&) = delete;
  HistoryWriter& operator=(const HistoryWriter&) = delete;
  void write(int iteration, Real wall_seconds, const IterationNorms& n,
             const std::map<std::string, ForceCoefficients>& forces, const std::vector<Real>& turbulence = {});
  void flush();

 private:
  std::FILE* file_ = nullptr;
  std::vector<std::string> groups_;
  std::size_t turbulence_ = 0;
};

void write_surface_csv(const std::string& path, const std::vector<WallFace>& faces);

}  // namespace narwhal
