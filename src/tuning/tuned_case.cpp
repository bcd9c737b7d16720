#include "tuning/tuned_case.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/units.hpp"
#include "io/case_edit.hpp"
#include "io/case_yaml.hpp"

namespace tearflow::tuning {

std::string tuned_yaml(const std::filesystem::path& case_file, const io::Case& tuned,
                       const std::filesystem::path& out, const std::string& header) {
  YAML::Node root = io::parse_yaml_file(case_file);
  // Files named relative to the case stay found from the tuned case's folder.
  io::relocate_case_paths(root, std::filesystem::absolute(case_file).parent_path(),
                          std::filesystem::absolute(out).parent_path());
  for (YAML::Node item : root["boundary_conditions"]) {
    const std::string face = item["face"].as<std::string>();
    for (const bc::BoundaryCondition& b : tuned.boundary_conditions) {
      const bc::RcrOutlet* rcr =
          b.outlet() ? std::get_if<bc::RcrOutlet>(&b.outlet()->law) : nullptr;
      if (b.face == face && rcr) {
        for (const char* key : {"resistance", "initial_distal_pressure"})
          item.remove(key);
        item["type"] = "rcr";
        // The shortest text that reads back as the same number: the tuned case holds the
        // run's outlets exactly, so the run's checkpoint starts it (run --start-from).
        item["proximal_resistance"] = fmt::format("{}", rcr->rcr.proximal_resistance);
        item["capacitance"] = fmt::format("{}", rcr->rcr.capacitance);
        item["distal_resistance"] = fmt::format("{}", rcr->rcr.distal_resistance);
      }
    }
  }
  YAML::Emitter emitter;
  emitter << root;
  return header + emitter.c_str() + "\n";
}

std::string table(const TuningResult& r, const TuningTargets& t) {
  const TuningStep& s = r.steps.back();
  std::string text = fmt::format("{:<14} {:>10} {:>10} {:>9}\n", "", "target", "achieved", "error");
  auto row = [&](const std::string& name, double target, double achieved, bool percent) {
    text += percent ? fmt::format("{:<14} {:>9.1f}% {:>9.1f}% {:>6.2f} pt\n", name, target,
                                  achieved, achieved - target)
                    : fmt::format("{:<14} {:>10.1f} {:>10.1f} {:>7.2f} %\n", name + " mmHg",
                                  target / units::mmHg, achieved / units::mmHg,
                                  100.0 * (achieved / target - 1.0));
  };
  row("P_sys", t.pressure.systolic, s.achieved.systolic, false);
  row("P_dias", t.pressure.diastolic, s.achieved.diastolic, false);
  row("MAP", t.pressure.mean, s.achieved.mean, false);
  for (size_t i = 0; i < t.splits.size(); ++i)
    row("split " + t.splits[i].face, 100.0 * t.splits[i].fraction, s.split_percent[i], true);
  return text;
}

nlohmann::json to_json(const TuningResult& r, const TuningTargets& t) {
  nlohmann::json j;
  j["met"] = r.met;
  j["method"] = {{"parameters", t.per_outlet ? "per_outlet" : "shared"},
                 {"correction", t.correct_domain ? "domain" : "aims"}};
  j["targets"] = {{"systolic_mmHg", t.pressure.systolic / units::mmHg},
                  {"diastolic_mmHg", t.pressure.diastolic / units::mmHg},
                  {"mean_mmHg", t.pressure.mean / units::mmHg}};
  for (const OutletFraction& o : t.splits)
    j["targets"]["split_percent"][o.face] = 100.0 * o.fraction;
  for (const TuningStep& s : r.steps) {
    nlohmann::json k = {{"iteration", s.iteration},
                        {"stage", s.iteration == 0 ? "0D" : "3D"},
                        {"R_T_Pa_s_per_m3", s.totals.resistance},
                        {"C_T_m3_per_Pa", s.totals.capacitance},
                        {"k_d", s.totals.distal_share},
                        {"systolic_mmHg", s.achieved.systolic / units::mmHg},
                        {"diastolic_mmHg", s.achieved.diastolic / units::mmHg},
                        {"mean_mmHg", s.achieved.mean / units::mmHg},
                        {"pressure_error_percent", 100.0 * s.pressure_error},
                        {"split_error_points", s.split_error},
                        {"domain_series_resistance_Pa_s_per_m3", s.domain.series}};
    for (size_t i = 0; i < t.splits.size(); ++i) {
      k["split_percent"][t.splits[i].face] = s.split_percent[i];
      k["distribution"][t.splits[i].face] = s.distribution[i];
      k["domain_branch_resistance_Pa_s_per_m3"][t.splits[i].face] = s.domain.of_branch(i);
    }
    j["steps"].push_back(k);
  }
  return j;
}

std::string commented(const std::string& text) {
  std::string out;
  for (size_t p = 0, q; p < text.size(); p = q + 1) {
    q = text.find('\n', p);
    out += "# " + text.substr(p, q - p) + "\n";
  }
  return out;
}

} // namespace tearflow::tuning
