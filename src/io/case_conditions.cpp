// The boundary conditions of a case file. Keys are checked twice: against every key any
// condition takes (a typo is unknown), then against the condition's type (a key of another
// type does not apply here).
#include "io/case_conditions.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <string>

#include <fmt/format.h>

#include "core/names.hpp"
#include "io/case_waveform.hpp"

namespace tearflow::io {

namespace {

namespace fs = std::filesystem;

/// One condition's mapping, with the readers every law's row uses.
class ConditionKeys {
public:
  ConditionKeys(const YamlValue& v, const fs::path& case_dir, std::vector<GivenWaveform>& periodic)
      : v_(v), case_dir_(case_dir), periodic_(periodic) {}
  const YamlValue& node() const { return v_; }
  /// The value of `x`, a waveform of quantity q in the condition's `units`.
  bc::Waveform waveform(const YamlValue& x, const Quantity& q) const {
    bc::Waveform w = read_case_waveform(x, v_.get("units"), q, case_dir_);
    if (!w.is_constant())
      periodic_.push_back({x, w});
    return w;
  }
  /// The required key's number, > 0 (`expected` says what it is).
  double positive(const char* key, const char* expected) const {
    return v_.require(key, expected).positive();
  }
  /// A constant pressure in `units` [Pa]; none when the key is absent.
  std::optional<double> constant_pressure(const char* key) const {
    const std::optional<YamlValue> x = v_.get(key);
    if (!x)
      return std::nullopt;
    const bc::Waveform w = waveform(*x, kPressure);
    if (!w.is_constant())
      x->fail_expected("a constant pressure (a number, in `units` if given)");
    return w(0.0);
  }

private:
  const YamlValue& v_;
  const fs::path& case_dir_;
  std::vector<GivenWaveform>& periodic_;
};

// --- the outlet laws' rows ----------------------------------------------------------------

bc::OutletLaw read_pressure_outlet(const ConditionKeys& k) {
  bc::PressureOutlet o;
  if (auto p = k.node().get("pressure"))
    o.pressure = k.waveform(*p, kPressure);
  else if (auto u = k.node().get("units"))
    u->fail("units applies to pressure, which is not given (it defaults to 0)");
  return o;
}

bc::OutletLaw read_resistance_outlet(const ConditionKeys& k) {
  return bc::ResistanceOutlet{k.positive("resistance", "the outlet resistance in Pa s/m^3, a "
                                                       "number > 0"),
                              k.constant_pressure("distal_pressure").value_or(0.0)};
}

bc::OutletLaw read_rcr_outlet(const ConditionKeys& k) {
  bc::RcrOutlet o;
  // R_p may be 0 (a two-element Windkessel); C and R_d must be > 0 for the ODE.
  o.rcr.proximal_resistance =
      k.node().require("proximal_resistance", "R_p in Pa s/m^3, a number >= 0").non_negative();
  o.rcr.capacitance = k.positive("capacitance", "C in m^3/Pa, a number > 0");
  o.rcr.distal_resistance = k.positive("distal_resistance", "R_d in Pa s/m^3, a number > 0");
  o.rcr.reference_pressure = k.constant_pressure("distal_pressure").value_or(0.0);
  o.initial_distal_pressure = k.constant_pressure("initial_distal_pressure");
  return o;
}

bc::OutletLaw read_rc_outlet(const ConditionKeys& k) {
  bc::RcOutlet o;
  o.resistance = k.positive("resistance", "R in Pa s/m^3, a number > 0");
  o.capacitance = k.positive("capacitance", "C in m^3/Pa, a number > 0");
  o.reference_pressure = k.constant_pressure("distal_pressure").value_or(0.0);
  o.initial_pressure = k.constant_pressure("initial_pressure");
  return o;
}

struct OutletRow {
  std::string_view type;              ///< the case file's `type:`
  std::vector<std::string_view> keys; ///< its own keys; `units` and `backflow_beta` go with all
  bc::OutletLaw (*read)(const ConditionKeys&);
};

/// The reader's table: one row per law of bc/outlet.hpp (docs/case-file.md documents them).
const std::array<OutletRow, 4>& outlet_rows() {
  static const std::array<OutletRow, 4> rows{{
      {"pressure", {"pressure"}, read_pressure_outlet},
      {"resistance", {"resistance", "distal_pressure"}, read_resistance_outlet},
      {"rcr",
       {"proximal_resistance", "capacitance", "distal_resistance", "distal_pressure",
        "initial_distal_pressure"},
       read_rcr_outlet},
      {"rc", {"resistance", "capacitance", "distal_pressure", "initial_pressure"}, read_rc_outlet},
  }};
  return rows;
}

const std::vector<std::string_view> kInflowKeys = {"flow", "units", "profile", "womersley_modes"};

bc::Inflow read_inflow(const ConditionKeys& k) {
  const YamlValue& v = k.node();
  bc::Inflow in;
  const YamlValue flow =
      v.require("flow", "the volume flow into the domain: a number (m3/s unless units "
                        "says otherwise) or a mapping with file or times/values");
  in.flow = k.waveform(flow, kFlow);
  // A human aorta's peak flow is about 0.5 L/s; 5 L/s and more is a flow in other units
  // read as m^3/s (300 mL/s read as 300 m^3/s ended in a Newton failure at step 1).
  double peak = std::abs(in.flow(0.0));
  for (int i = 1; !in.flow.is_constant() && i < 1000; ++i)
    peak = std::max(peak, std::abs(in.flow(in.flow.period() * i / 1000.0)));
  // Units may be given beside `flow` or inside its mapping: advice to add them where they
  // already are would send the user after the wrong fix.
  const bool units_given = v.has("units") || (flow.is_map() && flow.has("units"));
  if (peak > 5e-3)
    flow.fail(fmt::format("a peak of {:.4g} m^3/s ({:.4g} L/s) is no blood flow; {}", peak,
                          peak * 1e3,
                          units_given ? "check the values against the units given"
                                      : "the values are probably in mL/s: add `units: mL/s` "
                                        "to the boundary condition"));
  if (auto p = v.get("profile")) {
    const std::string profile = p->choice({"parabolic", "plug", "womersley"});
    in.profile = profile == "plug"        ? bc::ProfileShape::Plug
                 : profile == "womersley" ? bc::ProfileShape::Womersley
                                          : bc::ProfileShape::Parabolic;
    if (in.profile == bc::ProfileShape::Womersley && in.flow.is_constant())
      p->fail("profile womersley needs a periodic flow (file or times/values); use "
              "parabolic for a constant flow");
  }
  if (auto m = v.get("womersley_modes")) {
    if (in.profile != bc::ProfileShape::Womersley)
      m->fail("womersley_modes applies to profile: womersley only");
    in.womersley_modes = m->integer(1);
    // Each mode costs Bessel evaluations per inflow node and memory per node: a sampled
    // waveform has no harmonics that far up (the default is 16), and 1e6 ran for minutes.
    if (in.womersley_modes > 256)
      m->fail_expected("an integer from 1 to 256");
  }
  return in;
}

/// Every condition type, and every key any condition takes (from the table, once).
struct Vocabulary {
  std::vector<std::string_view> types, keys;
};

const Vocabulary& vocabulary() {
  static const Vocabulary v = [] {
    Vocabulary out{{"no_slip", "inflow"}, {"face", "type"}};
    out.keys.insert(out.keys.end(), kInflowKeys.begin(), kInflowKeys.end());
    for (const OutletRow& row : outlet_rows()) {
      out.types.push_back(row.type);
      for (std::string_view key : row.keys)
        if (std::find(out.keys.begin(), out.keys.end(), key) == out.keys.end())
          out.keys.push_back(key);
    }
    out.keys.push_back("backflow_beta");
    return out;
  }();
  return v;
}

bc::BoundaryCondition read_condition(const YamlValue& v, const fs::path& case_dir,
                                     std::vector<GivenWaveform>& periodic) {
  if (!v.is_map())
    v.fail_expected("a mapping with face, type and the type's keys");
  const Vocabulary& words = vocabulary();
  v.check_keys(words.keys);

  bc::BoundaryCondition bc;
  const YamlValue face = v.require("face", "the name of a mesh face");
  bc.face = face.text();
  if (bc.face.empty())
    face.fail_expected("the name of a mesh face");
  const YamlValue type_node = v.require(
      "type", join_names(std::vector<std::string>(words.types.begin(), words.types.end())));
  const std::string type = type_node.choice(words.types);

  // A key of another condition type (every key is one, checked above) is reported as not
  // applying here, with this type.
  auto check = [&](const std::vector<std::string_view>& own) {
    std::vector<std::string_view> allowed = {"face", "type"};
    allowed.insert(allowed.end(), own.begin(), own.end());
    v.check_keys(allowed, words.keys, "type: " + type);
  };
  const ConditionKeys keys(v, case_dir, periodic);
  if (type == "no_slip") {
    check({});
    bc.kind = bc::NoSlip{};
  } else if (type == "inflow") {
    check(kInflowKeys);
    bc.kind = read_inflow(keys);
  } else {
    const OutletRow& row = *std::find_if(outlet_rows().begin(), outlet_rows().end(),
                                         [&](const OutletRow& r) { return r.type == type; });
    std::vector<std::string_view> own = row.keys;
    own.insert(own.end(), {"units", "backflow_beta"});
    check(own);
    bc::Outlet outlet{row.read(keys)};
    if (auto beta = v.get("backflow_beta"))
      outlet.backflow_beta = beta->non_negative();
    bc.kind = std::move(outlet);
  }
  return bc;
}

} // namespace

std::vector<bc::BoundaryCondition> read_boundary_conditions(const YamlValue& v,
                                                            const fs::path& case_dir,
                                                            std::vector<GivenWaveform>& periodic) {
  const std::vector<YamlValue> items = v.items();
  if (items.empty())
    v.fail("expected at least one boundary condition");
  std::vector<bc::BoundaryCondition> bcs;
  std::map<std::string, YamlValue> first_use; // face -> its `face` key
  for (const YamlValue& item : items) {
    bcs.push_back(read_condition(item, case_dir, periodic));
    const YamlValue face = *item.get("face");
    if (auto [it, inserted] = first_use.emplace(bcs.back().face, face); !inserted)
      face.fail(fmt::format("face '{}' already has a boundary condition ({}, line {}); give "
                            "each face once",
                            bcs.back().face, it->second.path(), it->second.line()));
  }
  return bcs;
}

} // namespace tearflow::io
