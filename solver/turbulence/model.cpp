#include "turbulence/model.hpp"

#include "core/error.hpp"
#include "turbulence/baldwin_lomax.hpp"
#include "turbulence/launder_sharma.hpp"
#include "turbulence/menter_sst.hpp"
#include "turbulence/myong_kasagi.hpp"
#include "turbulence/nonlinear_k_epsilon.hpp"
#include "turbulence/spalart_allmaras.hpp"

namespace narwhal {

// The low-Re k-epsilon models' scheme: a start relaxed and once per cycle, then the
// model inside the smoothing with four full Newton steps per update (the coupled
// tail converges 4-6 times faster; from a uniform start this scheme diverges or
// finds the laminar plate solution). The start ends when the wall forces have
// settled to kLowReStartSpan over 25 cycles (turbulence/DESIGN.md, "the start").
namespace {
constexpr Real kLowReStartSpan = 1e-2;
TurbulenceModelInfo low_re_k_epsilon(const std::string& name, const std::string& summary) {
  return {name, summary, "points", "smoothing", 1.0, 4, {"cycle", 0.7, 1, kLowReStartSpan, 25}};
}
}  // namespace

const std::vector<TurbulenceModelInfo>& turbulence_models() {
  static const std::vector<TurbulenceModelInfo> models = {
      {"laminar", "no turbulence model"},
      {"baldwin-lomax", "Baldwin-Lomax algebraic model (turbulence/baldwin_lomax.hpp)"},
      {"sa", "Spalart-Allmaras one-equation model, SA-neg as on NASA TMR (turbulence/spalart_allmaras.hpp)", "lines",
       "smoothing"},
      low_re_k_epsilon("launder-sharma", "Launder-Sharma low-Re k-epsilon (turbulence/launder_sharma.hpp)"),
      low_re_k_epsilon("myong-kasagi", "Myong-Kasagi low-Re k-epsilon (turbulence/myong_kasagi.hpp)"),
      low_re_k_epsilon("nonlinear-k-epsilon",
                       "the paper's low-Re non-linear (quadratic stress) k-epsilon on Myong-Kasagi "
                       "(turbulence/nonlinear_k_epsilon.hpp)"),
      {"sst", "Menter SST k-omega, the 2003 version as on NASA TMR (turbulence/menter_sst.hpp)", "lines", "smoothing",
       1.0, 2},
  };
  return models;
}

const TurbulenceModelInfo* find_turbulence_model(const std::string& name) {
  for (const auto& m : turbulence_models())
    if (m.name == name) return &m;
  return nullptr;
}

TurbulenceSettings with_model_defaults(TurbulenceSettings s) {
  const TurbulenceModelInfo fallback;  // unknown names: make_turbulence_model reports them
  const TurbulenceModelInfo* found = find_turbulence_model(s.model);
  const TurbulenceModelInfo& info = found ? *found : fallback;
  if (s.smoother.empty()) s.smoother = info.smoother;
  if (s.coupling.empty()) s.coupling = info.coupling;
  if (!s.relaxation) s.relaxation = info.relaxation;
  if (!s.iterations) s.iterations = info.iterations;
  if (s.start.coupling.empty()) s.start.coupling = info.start.coupling;
  if (!s.start.relaxation) s.start.relaxation = info.start.relaxation;
  if (!s.start.iterations) s.start.iterations = info.start.iterations;
  if (!s.start.force_span) s.start.force_span = info.start.force_span;
  return s;
}

std::unique_ptr<TurbulenceModel> make_turbulence_model(const TurbulenceSettings& s, const Grid& g,
                                                       const Communicator& comm) {
  if (s.model == "laminar") return nullptr;
  if (s.model == "baldwin-lomax") return std::make_unique<BaldwinLomax>(s, g);
  if (s.model == "sa") return std::make_unique<SpalartAllmaras>(s, g, comm);
  if (s.model == "sst") return std::make_unique<MenterSst>(s, g, comm);
  if (s.model == "myong-kasagi") return std::make_unique<MyongKasagi>(s, g, comm);
  if (s.model == "nonlinear-k-epsilon") return std::make_unique<NonlinearKEpsilon>(s, g, comm);
  if (s.model == "launder-sharma") return std::make_unique<LaunderSharma>(s, g, comm);
  std::string valid;
  for (const auto& m : turbulence_models()) valid += (valid.empty() ? "" : ", ") + ("'" + m.name + "'");
  fail("unknown turbulence model '{}': valid models are {}", s.model, valid);
}

}  // namespace narwhal
