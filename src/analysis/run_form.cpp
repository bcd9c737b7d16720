#include "analysis/run_form.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "io/case.hpp"

namespace tearflow::analysis {

namespace {

ContinuityForm form_of(const io::Case& c) {
  ContinuityForm f;
  f.time_step = c.time.step;
  f.fluid = c.fluid;
  f.scheme = physics::GeneralizedAlpha::from_spectral_radius(c.time.spectral_radius);
  return f;
}

bool same_folder(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec) && !ec;
}

} // namespace

std::optional<ContinuityForm> find_continuity_form(const std::filesystem::path& run_dir,
                                                   const std::filesystem::path& case_file) {
  if (!case_file.empty())
    return form_of(io::load_case(case_file));
  // A case that does not read (moved mesh, older keys) or writes elsewhere is not this run's.
  for (const char* name : {"tuned.yaml", "case.yaml"}) {
    const std::filesystem::path candidate = run_dir.parent_path() / name;
    if (!std::filesystem::exists(candidate))
      continue;
    try {
      const io::Case c = io::load_case(candidate);
      if (same_folder(c.output.directory, run_dir))
        return form_of(c);
    } catch (const InputError&) {
    }
  }
  return std::nullopt;
}

std::vector<double> step_times(const std::filesystem::path& run_dir) {
  std::ifstream in(RunFiles{run_dir}.faces_csv());
  std::string line;
  if (!in || !std::getline(in, line) || line.rfind("step,time_s,", 0) != 0)
    return {};
  std::map<long, double> step_time; // one row per face and step
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string step, t;
    if (std::getline(row, step, ',') && std::getline(row, t, ','))
      step_time[std::stol(step)] = std::stod(t);
  }
  std::vector<double> times;
  for (const auto& [step, t] : step_time)
    times.push_back(t);
  return times;
}

std::optional<double> step_ending_at(const std::vector<double>& times, double time,
                                     double fallback) {
  // Frame times are printed with 10 significant digits (io/vtu_series.cpp).
  const double slack = 1e-9 * std::max(1.0, std::abs(time));
  const auto it = std::lower_bound(times.begin(), times.end(), time - slack);
  if (it == times.end() || std::abs(*it - time) > slack)
    return fallback;
  if (it == times.begin())
    return std::nullopt;
  return *it - *std::prev(it);
}

} // namespace tearflow::analysis
