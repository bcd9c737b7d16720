#include "tuning/targets.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/units.hpp"
#include "io/case_yaml.hpp"

namespace tearflow::tuning {

TuningTargets load_targets(const std::filesystem::path& file) {
  const io::YamlValue root(file.string(), io::parse_yaml_file(file));
  root.check_keys({"pressure", "splits", "tolerance", "iterations", "cycles", "domain_resistance",
                   "parameters", "correction", "in_run"});
  TuningTargets t;

  const io::YamlValue p =
      root.require("pressure", "{systolic, diastolic, mean, units} at the inlet");
  p.check_keys({"systolic", "diastolic", "mean", "units"});
  const double scale =
      p.has("units") ? units::pressure_scale(p.get("units")->text(), p.get("units")->where()) : 1.0;
  t.pressure.systolic = scale * p.require("systolic", "P_sys, a number > 0").positive();
  t.pressure.diastolic = scale * p.require("diastolic", "P_dias, a number > 0").positive();
  t.pressure.mean = scale * p.require("mean", "MAP, a number > 0").positive();
  if (!(t.pressure.diastolic < t.pressure.mean && t.pressure.mean < t.pressure.systolic))
    p.fail(fmt::format("no Windkessel can meet these pressures: expected diastolic < mean < "
                       "systolic, got {} / {} / {}",
                       p.get("diastolic")->text(), p.get("mean")->text(),
                       p.get("systolic")->text()));

  const io::YamlValue s = root.require("splits", "{outlet face: percent of the total outflow}");
  double sum = 0.0;
  for (const auto& [face, value] : s.entries()) {
    const double percent = value.positive();
    t.splits.push_back({face, percent});
    sum += percent;
  }
  if (t.splits.empty())
    s.fail_expected("at least one outlet with its percent of the total outflow");
  // Measured splits are rounded to 0.1 %: four outlets can miss 100 by 0.2.
  if (std::abs(sum - 100.0) > 0.5)
    s.fail(
        fmt::format("the splits sum to {:.2f} %, expected 100 % (within 0.5 for rounding)", sum));
  for (OutletFraction& o : t.splits)
    o.fraction /= sum;

  if (auto tol = root.get("tolerance")) {
    tol->check_keys({"pressure_percent", "split_points"});
    if (auto x = tol->get("pressure_percent"))
      t.pressure_tolerance = x->positive() / 100.0;
    if (auto x = tol->get("split_points"))
      t.split_tolerance = x->positive();
  }
  if (auto x = root.get("iterations"))
    t.max_iterations = x->integer(0);
  if (auto x = root.get("cycles"))
    t.cycles = x->integer(1);
  if (auto x = root.get("domain_resistance"))
    t.domain_resistance = x->non_negative();
  if (auto x = root.get("parameters"))
    t.per_outlet = x->choice({"shared", "per_outlet"}) == "per_outlet";
  if (auto x = root.get("correction")) {
    t.correct_domain = x->choice({"domain", "aims"}) == "domain";
    if (t.per_outlet && !t.correct_domain)
      x->fail("per-outlet parameters are corrected by the domain's resistance to each outlet: "
              "use correction: domain (the default) with parameters: per_outlet");
  }
  if (auto x = root.get("in_run"))
    t.in_run = x->choice({"true", "false"}) == "true";
  return t;
}

} // namespace tearflow::tuning
