// Measured flows to a case and its targets (measured_case.hpp).
#include "mri/measured_case.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "io/case.hpp"
#include "io/case_edit.hpp"
#include "io/case_yaml.hpp"
#include "io/durable_file.hpp"

namespace tearflow::mri {

namespace fs = std::filesystem;

std::vector<OutletSplit> outlet_splits(const std::vector<std::string>& tunable,
                                       const std::optional<VesselFlow>& inlet,
                                       const std::vector<VesselFlow>& outlets,
                                       const std::string& where) {
  std::vector<OutletSplit> splits;
  std::vector<std::string> missing;
  double measured = 0.0;
  std::vector<double> mean(tunable.size(), 0.0);
  for (const VesselFlow& o : outlets)
    if (std::find(tunable.begin(), tunable.end(), o.name) == tunable.end())
      input_error("{}: scan for '{}', which is not an rcr or resistance outlet of the case (those "
                  "are: {}); tuning sets only those",
                  where, o.name, fmt::join(tunable, ", "));
  for (std::size_t i = 0; i < tunable.size(); ++i) {
    auto it = std::find_if(outlets.begin(), outlets.end(),
                           [&](const VesselFlow& o) { return o.name == tunable[i]; });
    if (it == outlets.end()) {
      missing.push_back(tunable[i]);
      continue;
    }
    mean[i] = it->mean_flow();
    if (!(mean[i] > 0))
      input_error("{}: the scan for '{}' gives a mean flow of {:.2f} mL/s along its vessel, not "
                  "positive (seed: {}); check its seed and the landmark's direction (or the "
                  "scanner's phase sign: give the seed as FOLDER@X,Y,Z instead)",
                  where, it->name, mean[i] / units::mL, it->seed_from);
    measured += mean[i];
  }
  if (missing.size() > 1 || (missing.size() == 1 && !inlet))
    input_error("{}: no scan for the outlet(s) {}; every rcr / resistance outlet needs one, or all "
                "but one when the inflow is scanned too (that one then takes the rest)",
                where, fmt::join(missing, ", "));
  double total = measured;
  if (missing.size() == 1) {
    const double rest = inlet->mean_flow() - measured;
    if (!(rest > 0))
      input_error("{}: the measured outlets carry {:.2f} mL/s on average, the inflow {:.2f} mL/s; "
                  "nothing is left for '{}' (scan it, or check the seeds and the vessels' flow)",
                  where, measured / units::mL, inlet->mean_flow() / units::mL, missing.front());
    total = inlet->mean_flow();
    mean[std::find(tunable.begin(), tunable.end(), missing.front()) - tunable.begin()] = rest;
  }
  for (std::size_t i = 0; i < tunable.size(); ++i)
    splits.push_back({tunable[i], 100.0 * mean[i] / total,
                      tunable[i] == (missing.empty() ? "" : missing.front())
                          ? "inflow minus the measured outlets"
                          : "measured"});
  return splits;
}

nlohmann::json write_measured_case(const MeasuredFlows& flows, const fs::path& dir) {
  const std::string where = fmt::format("case '{}'", flows.case_file.string());
  const io::Case c = io::load_case(flows.case_file);
  std::vector<std::string> inflow_faces, tunable;
  for (const bc::BoundaryCondition& b : c.boundary_conditions) {
    if (b.inflow())
      inflow_faces.push_back(b.face);
    if (const bc::Outlet* o = b.outlet();
        o && (std::holds_alternative<bc::RcrOutlet>(o->law) ||
              std::holds_alternative<bc::ResistanceOutlet>(o->law)))
      tunable.push_back(b.face);
  }
  if (flows.inlet && inflow_faces.size() != 1)
    input_error("{}: {} inflow faces; the measured inflow goes to the case's one inflow face",
                where, inflow_faces.size());
  // Everything checked before a file is written (no case beside stale targets).
  for (std::size_t i = 0; i < flows.outlets.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (flows.outlets[i].name == flows.outlets[j].name)
        input_error("{}: two scans for the outlet '{}'; one per outlet", where,
                    flows.outlets[i].name);
  if (flows.inlet && !(flows.inlet->mean_flow() > 0))
    input_error("{}: the inflow scan's mean flow along its vessel is {:.2f} mL/s, not positive "
                "(seed: {}); a landmark's normal must point downstream (or the scanner's phase "
                "sign is the other way: give the seed as FOLDER@X,Y,Z instead)",
                where, flows.inlet->mean_flow() / units::mL, flows.inlet->seed_from);
  std::vector<OutletSplit> splits;
  if (!flows.outlets.empty()) {
    if (!flows.pressure)
      input_error("{}: outlet scans give the flow splits; the targets file needs the inlet's "
                  "measured pressures too (--pressure SYS/DIA/MEAN, e.g. 126/60/86mmHg: cuff "
                  "or catheter; 2D scans do not measure pressure)",
                  where);
    splits = outlet_splits(tunable, flows.inlet, flows.outlets, where);
  }
  fs::create_directories(dir);
  nlohmann::json summary;

  YAML::Node root = io::parse_yaml_file(flows.case_file);
  io::relocate_case_paths(root, fs::absolute(flows.case_file).parent_path(), fs::absolute(dir));
  std::string header = "# Written by `tearflow mri inflow` from 2D phase-contrast scans";
  if (flows.inlet) {
    const VesselFlow& in = *flows.inlet;
    const bc::Waveform w = in.waveform();
    const double step = c.time.step;
    const int samples = std::max(3, static_cast<int>(std::lround(in.period / step)));
    const double period = samples * step; // a whole number of the case's steps
    std::string csv = fmt::format("# inflow of case '{}' from scan '{}' (seed: {}): one R-R "
                                  "interval of {:.1f} ms (measured {:.2f} ms) at the case's step\n"
                                  "time_s,flow_mL_per_s\n",
                                  c.name, in.name, in.seed_from, period * 1e3, in.period * 1e3);
    double mean = 0.0;
    for (int j = 0; j < samples; ++j) {
      const double q = w(j * step * in.period / period);
      mean += q / samples;
      csv += fmt::format("{:.6g},{:.8g}\n", j * step, q / units::mL);
    }
    io::write_file_atomically(dir / "inflow.csv", csv);
    for (YAML::Node item : root["boundary_conditions"])
      if (item["face"].as<std::string>() == inflow_faces.front()) {
        item.remove("units");
        YAML::Node flow;
        flow["file"] = "inflow.csv";
        flow["units"] = "mL/s";
        flow["period"] = fmt::format("{}", period);
        item["flow"] = flow;
      }
    if (root["time"] && root["time"]["period"])
      root["time"]["period"] = fmt::format("{}", period);
    header += fmt::format("; inflow from '{}': mean {:.2f} mL/s, R-R {:.1f} ms", in.name,
                          mean / units::mL, period * 1e3);
    summary["inflow"] = {{"face", inflow_faces.front()},
                         {"scan", in.name},
                         {"period_s", period},
                         {"measured_period_s", in.period},
                         {"mean_mL_per_s", mean / units::mL},
                         {"frame_mean_mL_per_s", in.mean_flow() / units::mL},
                         {"samples", samples}};
  }
  YAML::Emitter emitter;
  emitter << root;
  io::write_file_atomically(dir / "case.yaml", header + "\n" + emitter.c_str() + "\n");
  // The case as `run` and `tune` will read it (another periodic waveform of the case keeps its
  // own period, which may now disagree with the measured one).
  try {
    io::load_case(dir / "case.yaml");
  } catch (const InputError& e) {
    input_error("{}: the case written with the measured inflow, '{}', does not load: {}", where,
                (dir / "case.yaml").string(), e.what());
  }

  if (!flows.outlets.empty()) {
    const auto& p = *flows.pressure;
    std::string text = "# Targets from 2D phase contrast (`tearflow mri inflow`): outlet splits "
                       "from the cycle-mean flows\n";
    text += fmt::format("pressure: {{systolic: {:.6g}, diastolic: {:.6g}, mean: {:.6g}, units: "
                        "mmHg}}\nsplits:\n",
                        p[0] / units::mmHg, p[1] / units::mmHg, p[2] / units::mmHg);
    for (const OutletSplit& s : splits) {
      text += fmt::format("  {}: {:.4g}   # {}\n", s.face, s.percent, s.source);
      summary["splits_percent"][s.face] = s.percent;
      summary["split_source"][s.face] = s.source;
    }
    io::write_file_atomically(dir / "targets.yaml", text);
    if (flows.inlet && splits.size() == flows.outlets.size()) {
      double out = 0.0;
      for (const VesselFlow& o : flows.outlets)
        out += o.mean_flow();
      // Mass balance of the scans: what the outlets carry off against the inflow.
      summary["outflow_over_inflow"] = out / flows.inlet->mean_flow();
    }
  }
  return summary;
}

} // namespace tearflow::mri
