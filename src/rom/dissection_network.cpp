#include "rom/dissection_network.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bc/outlet.hpp"
#include "bc/windkessel_network.hpp"
#include "core/error.hpp"
#include "core/units.hpp"

namespace tearflow::rom {

using nlohmann::json;

double RomCoefficients::tear_coefficient(const std::string& name) const {
  const auto it = tear.find(name);
  return it == tear.end() ? tear_loss : it->second;
}

double RomCoefficients::size_exponent(const std::string& name) const {
  const auto it = tear_size.find(name);
  return it == tear_size.end() ? 0.0 : it->second;
}

RomInputs rom_inputs(const io::Case& c, const DissectionGeometry& g, double wall_thickness) {
  RomInputs in;
  in.density = c.fluid.density, in.viscosity = c.fluid.viscosity;
  const std::string source = c.file.empty() ? c.name : c.file.string();
  bool has_inflow = false;
  for (const bc::BoundaryCondition& b : c.boundary_conditions) {
    if (const auto* inflow = std::get_if<bc::Inflow>(&b.kind)) {
      if (b.face != "inlet")
        input_error("{}: the inflow is on face '{}'; the reduced-order model feeds the face "
                    "'inlet' (the landmark 'inlet')",
                    source, b.face);
      in.inflow = inflow->flow, has_inflow = true;
    } else if (const auto* outlet = std::get_if<bc::Outlet>(&b.kind)) {
      const std::optional<bc::WindkesselRCR> rcr = bc::zero_d_branch(outlet->law);
      if (!rcr)
        input_error("{}: outlet '{}' sets the pressure; the reduced-order model takes RCR, RC "
                    "and resistance outlets",
                    source, b.face);
      if (g.node(b.face) < 0)
        input_error("{}: outlet '{}' is not a cap of the model (its caps: outlet and the "
                    "branches' planar faces)",
                    source, b.face);
      in.outlets.emplace_back(b.face, *rcr);
    }
  }
  if (!has_inflow || in.inflow.period() <= 0.0)
    input_error("{}: the reduced-order model needs a periodic inflow on face 'inlet'", source);
  if (in.outlets.empty())
    input_error("{}: no outlets", source);
  if (c.solid) {
    WallProperties w;
    w.youngs_modulus = c.solid->material.youngs_modulus();
    w.poisson_ratio = c.solid->material.poisson_ratio();
    w.thickness = wall_thickness > 0.0 ? wall_thickness : g.wall_thickness;
    if (!(w.thickness > 0.0))
      input_error("{}: a compliant wall, but the model has no wall region to measure its "
                  "thickness from; give --wall-thickness",
                  source);
    for (const bc::RobinSupport& s : c.solid->conditions.supports)
      if (s.face == "outer_wall")
        w.support_stiffness = s.stiffness;
    in.wall = w;
  }
  return in;
}

double flap_width(double r, double f) {
  const double target = 2.0 * M_PI * std::clamp(std::min(f, 1.0 - f), 0.0, 0.5);
  double lo = 0.0, hi = M_PI;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (mid - std::sin(mid) < target ? lo : hi) = mid;
  }
  return 2.0 * r * std::sin(0.25 * (lo + hi));
}

namespace {

/// Per node: its length (half its segments'), and dA/dp of its lumen's wall and of its flap.
struct NodeLaw {
  double length = 0.0, outer = 0.0, flap = 0.0; ///< [m], [m^2/Pa], [m^2/Pa]
};

std::vector<NodeLaw> node_laws(const DissectionGeometry& g, const RomInputs& in,
                               const RomCoefficients& k) {
  std::vector<NodeLaw> law(g.nodes.size());
  for (const GeometrySegment& s : g.segments) {
    law[g.node(s.from)].length += 0.5 * s.length;
    law[g.node(s.to)].length += 0.5 * s.length;
  }
  if (!in.wall)
    return law;
  const WallProperties& w = *in.wall;
  const double e_hoop = w.youngs_modulus / (1.0 - w.poisson_ratio * w.poisson_ratio);
  const double bending = w.youngs_modulus * std::pow(w.thickness, 3) /
                         (12.0 * (1.0 - w.poisson_ratio * w.poisson_ratio));
  for (size_t i = 0; i < g.nodes.size(); ++i) {
    const GeometryNode& n = g.nodes[i];
    const double r = std::sqrt(n.total_area / M_PI);
    const double section = 2.0 * M_PI * r / (e_hoop * w.thickness / (r * r) + w.support_stiffness);
    law[i].outer = section * n.area / n.total_area;
    if (!n.partner.empty()) {
      const double b = flap_width(r, n.area / n.total_area);
      law[i].flap = k.flap * std::pow(b, 5) / (720.0 * bending);
    }
  }
  return law;
}

bool is_arch(const GeometrySegment& s) {
  return s.lumen == "aorta" && (s.from == "AAo" || s.from.rfind("arch_", 0) == 0);
}

/// A junction at a tear's TL node: the segment whose flow arrives there in the TL's channel
/// and the segment that leads on (indices into the segments, -1 if none).
struct Junction {
  int approach = -1, onward = -1;
};

/// A dividing junction (the entry): the aorta segment that arrives from an aorta node and the
/// TL segment that leaves.
Junction entry_junction(const DissectionGeometry& g, int node) {
  Junction j;
  for (size_t i = 0; i < g.segments.size(); ++i) {
    const GeometrySegment& s = g.segments[i];
    if (g.node(s.to) == node && s.lumen == "aorta" && g.nodes[g.node(s.from)].lumen == "aorta")
      j.approach = static_cast<int>(i);
    if (g.node(s.from) == node && s.lumen == "TL")
      j.onward = static_cast<int>(i);
  }
  return j;
}

/// A combining junction at a tear's TL node (the exit, where the FL's flow rejoins): the TL
/// segment that arrives there (the run) and the segment that leaves it for an aorta node (the
/// combined flow onward); indices into the segments, -1 if none. Any tear whose TL node leads
/// on into the undivided aorta is one (also an exit that lies on DAo_dist; its landmark then
/// reports the node's pressure alone, not a section mean as DAo_prox's).
Junction exit_junction(const DissectionGeometry& g, int node) {
  Junction j;
  for (size_t i = 0; i < g.segments.size(); ++i) {
    const GeometrySegment& s = g.segments[i];
    if (g.node(s.to) == node && s.lumen == "TL")
      j.approach = static_cast<int>(i);
    if (g.node(s.from) == node && g.nodes[g.node(s.to)].lumen == "aorta")
      j.onward = static_cast<int>(i);
  }
  return j;
}

} // namespace

LumpedNetwork build_network(const DissectionGeometry& g, const RomInputs& in,
                            const RomCoefficients& k,
                            const std::map<std::string, double>& tear_areas) {
  const std::vector<NodeLaw> law = node_laws(g, in, k);
  std::vector<NetworkNode> nodes;
  for (size_t i = 0; i < g.nodes.size(); ++i)
    nodes.push_back({g.nodes[i].name, law[i].length * law[i].outer});
  std::vector<NetworkCoupling> couplings;
  for (size_t i = 0; i < g.nodes.size(); ++i)
    if (g.nodes[i].lumen == "TL" && !g.nodes[i].partner.empty() && law[i].flap > 0.0)
      couplings.push_back(
          {static_cast<int>(i), g.node(g.nodes[i].partner), law[i].length * law[i].flap});

  double arch_segments = 0.0;
  for (const GeometrySegment& s : g.segments)
    arch_segments += is_arch(s) ? 1.0 : 0.0;
  const int aao = g.node("AAo");
  const double arch_loss =
      aao >= 0 && arch_segments > 0.0
          ? k.arch_loss * 0.5 * in.density / (g.nodes[aao].area * g.nodes[aao].area) / arch_segments
          : 0.0;
  std::vector<NetworkEdge> edges;
  for (const GeometrySegment& s : g.segments) {
    NetworkEdge e{s.from + "-" + s.to, g.node(s.from), g.node(s.to)};
    e.resistance = k.viscous * 8.0 * M_PI * in.viscosity * s.inverse_area_squared;
    e.inertance = in.density * s.inverse_area;
    e.area_from = g.nodes[e.from].area, e.area_to = g.nodes[e.to].area;
    const bool lumen = s.lumen == "TL" || s.lumen == "FL";
    e.loss = (is_arch(s) ? arch_loss : 0.0) +
             (lumen ? k.friction * 0.5 * in.density * s.friction_integral : 0.0);
    edges.push_back(e);
  }
  const double h = in.wall ? in.wall->thickness : (g.wall_thickness > 0 ? g.wall_thickness : 2e-3);
  for (const GeometryTear& t : g.tears) {
    const auto it = tear_areas.find(t.name);
    const double a = it == tear_areas.end() ? t.area : it->second;
    if (!(a > 0.0))
      input_error("tear '{}': area {} m^2 (expected > 0)", t.name, a);
    NetworkEdge e{"tear_" + t.name, g.node(t.tl_node), g.node(t.fl_node)};
    e.resistance = 8.0 * M_PI * in.viscosity * h / (a * a);
    e.inertance = in.density * (h + 1.7 * std::sqrt(a / M_PI)) / a;
    // The tear and the TL's channel beside it in series (file comment); a tear without a
    // measured channel (geometry.json refuses one) would be an orifice alone.
    const double a_j = t.channel_area;
    const double channel = a_j > 0.0 ? 1.0 / (a_j * a_j) : 0.0;
    e.loss = k.tear_coefficient(t.name) * std::pow(a / t.area, k.size_exponent(t.name)) * 0.5 *
             in.density * (1.0 / (a * a) + channel);
    // A tear the undivided aorta feeds (its TL node ends an aorta segment: the entry) is a
    // dividing junction, one that leads on into it (the exit) a combining one (file
    // comment). Either way the node is the TL's channel beside the tear, and the segment
    // onward carries the head of the flow that arrives there in the channel: the aorta's
    // approaching flow at the entry, the TL's own at the exit.
    Junction j = entry_junction(g, g.node(t.tl_node));
    if (j.approach < 0)
      j = exit_junction(g, g.node(t.tl_node));
    if (j.approach >= 0 && t.channel_area > 0.0) {
      edges[j.approach].area_to = a_j; // edges are the segments', in order
      if (j.onward >= 0) {
        edges[j.onward].area_from = a_j;
        edges[j.onward].regain_edge = j.approach;
        edges[j.onward].regain = 0.5 * in.density / (a_j * a_j);
      }
    }
    edges.push_back(e);
  }
  std::vector<NetworkOutlet> outlets;
  for (const auto& [face, rcr] : in.outlets)
    outlets.push_back({face, g.node(face), rcr});
  return LumpedNetwork(std::move(nodes), std::move(edges), std::move(couplings), std::move(outlets),
                       g.node("inlet"), in.inflow, in.density);
}

analysis::Analysis network_analysis(const LumpedNetwork& net, const NetworkSolution& s,
                                    const DissectionGeometry& g, const RomInputs& in,
                                    const RomCoefficients& k,
                                    const geometry::Landmarks& landmarks) {
  const std::vector<NodeLaw> law = node_laws(g, in, k);
  analysis::Analysis a;
  a.source = "reduced-order model";
  a.frames = fmt::format("periodic state (cycle {})", s.cycles);
  a.flow_method = "reduced-order model";
  const double t0 = s.time.front(), period = net.period();
  const size_t frames = s.time.size() + 1; // the cycle closed by its first state
  for (size_t f = 0; f < frames; ++f)
    a.time.push_back(f < s.time.size() ? s.time[f] - t0 : period);
  const auto& edges = net.edges();
  for (const geometry::Landmark& l : landmarks.planes) {
    const int i = net.node(l.name);
    if (i < 0)
      continue;
    analysis::LandmarkSeries series{l, {}};
    // The entry's TL node is a landmark plane that cuts both the TL's channel beside the tear
    // (A_j, where the node's pressure is) and the FL's blind end above it (the rest of the
    // section, at the FL's pressure beside the tear): the section's mean pressure, as
    // `analyze` measures it in a 3D run, is their area-weighted mean.
    const GeometryTear* blind = nullptr;
    for (const GeometryTear& t : g.tears)
      if (g.node(t.tl_node) == i && entry_junction(g, i).approach >= 0 && t.channel_area > 0.0 &&
          t.channel_area < g.nodes[i].area)
        blind = &t;
    for (size_t f = 0; f < frames; ++f) {
      const size_t m = f % s.time.size();
      double in_flow = 0.0, out_flow = 0.0;
      for (size_t e = 0; e < edges.size(); ++e) {
        if (edges[e].to == i)
          in_flow += s.flow[m][e];
        if (edges[e].from == i)
          out_flow += s.flow[m][e];
      }
      if (i == g.node("inlet"))
        in_flow += in.inflow(s.time[m]);
      for (size_t o = 0; o < net.outlets().size(); ++o)
        if (net.outlets()[o].node == i)
          out_flow += s.outflow[m][o];
      analysis::SectionValues v;
      v.flow = 0.5 * (in_flow + out_flow);
      const double p = s.pressure[m][i];
      const GeometryNode& n = g.nodes[i];
      const double dp = n.partner.empty() ? 0.0 : p - s.pressure[m][g.node(n.partner)];
      v.area = n.area + law[i].outer * p + (n.lumen == "FL" ? -1.0 : 1.0) * law[i].flap * dp;
      v.pressure = p;
      if (blind) {
        const double w = blind->channel_area / n.area; // the channel's share of the section
        v.pressure = w * p + (1.0 - w) * s.pressure[m][g.node(blind->fl_node)];
      }
      v.max_velocity = std::nan("");
      v.wall_displacement = std::nan("");
      series.samples.push_back(v);
    }
    a.series.push_back(std::move(series));
  }
  analysis::mark_cycle_events(a);

  // The faces' record, as cycles.json gives it for a 3D cycle.
  json faces;
  double total = 0.0;
  std::vector<double> volume(net.outlets().size(), 0.0);
  for (size_t o = 0; o < net.outlets().size(); ++o) {
    for (size_t f = 0; f + 1 < frames; ++f)
      volume[o] += s.outflow[f][o] * (a.time[f + 1] - a.time[f]);
    total += volume[o];
  }
  for (size_t o = 0; o < net.outlets().size(); ++o)
    faces[net.outlets()[o].name] = {{"net_outflow_volume_m3", volume[o]},
                                    {"flow_split_percent", 100.0 * volume[o] / total}};
  double p_sys = -1e300, p_dia = 1e300, p_mean = 0.0;
  const int inlet = g.node("inlet");
  for (size_t f = 0; f + 1 < frames; ++f) {
    const double p = s.pressure[f][inlet];
    p_sys = std::max(p_sys, p), p_dia = std::min(p_dia, p);
    p_mean += p * (a.time[f + 1] - a.time[f]) / period;
  }
  faces["inlet"] = {{"net_outflow_volume_m3", -total},
                    {"systolic_pressure_mmHg", p_sys / units::mmHg},
                    {"diastolic_pressure_mmHg", p_dia / units::mmHg},
                    {"mean_pressure_mmHg", p_mean / units::mmHg}};
  a.cycle = {{"cycle", s.cycles}, {"faces", faces}};
  return a;
}

Prediction predict(const DissectionGeometry& g, const RomInputs& in, const RomCoefficients& k,
                   const geometry::Landmarks& landmarks,
                   const std::map<std::string, double>& tear_areas,
                   const IntegrationOptions& options) {
  const LumpedNetwork net = build_network(g, in, k, tear_areas);
  // Start from the periodic state at t = 0 of the outlets with the wall's compliance beside
  // them (a capacitor that passes no mean flow: R_d of 1e6 outlet resistances), exact in the
  // frequency domain (bc/windkessel_network.hpp): the network's slowest mode, the outlets'
  // and the wall's capacitors draining through the outlets, then starts near its periodic
  // state, and the cycles to periodicity drop from ~9 to ~3 with a compliant wall.
  std::vector<bc::WindkesselBranch> branches;
  double largest = 0.0;
  for (const auto& [face, rcr] : in.outlets) {
    branches.push_back({face, rcr});
    largest = std::max(largest, rcr.proximal_resistance + rcr.distal_resistance);
  }
  double wall = 0.0;
  for (const NetworkNode& n : net.nodes())
    wall += n.compliance;
  if (wall > 0.0)
    branches.push_back({"wall", {0.0, wall, 1e6 * largest, 0.0}});
  const bc::PeriodicState start = bc::WindkesselNetwork(branches).periodic(in.inflow);
  std::vector<double> distal;
  for (size_t o = 0; o < in.outlets.size(); ++o)
    distal.push_back(branches[o].has_capacitor() ? start.distal_pressure(o, 0.0) : 0.0);
  Prediction p;
  p.solution = net.periodic(start.node_pressure(0.0), distal, options);
  p.analysis = network_analysis(net, p.solution, g, in, k, landmarks);
  return p;
}

json to_json(const RomCoefficients& k) {
  json j{{"viscous_factor", k.viscous},          {"friction_factor", k.friction},
         {"arch_loss_coefficient", k.arch_loss}, {"flap_compliance_factor", k.flap},
         {"tear_loss_coefficient", k.tear_loss}, {"tears", json::object()},
         {"tear_size_exponents", json::object()}};
  for (const auto& [name, value] : k.tear)
    j["tears"][name] = value;
  for (const auto& [name, value] : k.tear_size)
    j["tear_size_exponents"][name] = value;
  return j;
}

RomCoefficients coefficients_from_json(const json& j, const std::string& source) {
  RomCoefficients k;
  auto number = [&](const char* key, double& out) {
    if (!j.contains(key))
      input_error("{}: missing '{}' (docs/rom.md)", source, key);
    if (!j[key].is_number() || !(j[key].get<double>() >= 0.0))
      input_error("{}: '{}' must be a number >= 0", source, key);
    out = j[key].get<double>();
  };
  number("viscous_factor", k.viscous);
  number("friction_factor", k.friction);
  number("arch_loss_coefficient", k.arch_loss);
  number("flap_compliance_factor", k.flap);
  number("tear_loss_coefficient", k.tear_loss);
  if (j.contains("tear_size_exponents")) { // may be negative
    if (!j["tear_size_exponents"].is_object())
      input_error("{}: 'tear_size_exponents' must map tear names to exponents", source);
    for (const auto& [name, v] : j["tear_size_exponents"].items()) {
      if (!v.is_number())
        input_error("{}: tear_size_exponents.{} must be a number", source, name);
      k.tear_size[name] = v.get<double>();
    }
  }
  if (j.contains("tears")) {
    if (!j["tears"].is_object())
      input_error("{}: 'tears' must map tear names to loss coefficients", source);
    for (const auto& [name, v] : j["tears"].items()) {
      if (!v.is_number() || !(v.get<double>() >= 0.0))
        input_error("{}: tears.{} must be a number >= 0", source, name);
      k.tear[name] = v.get<double>();
    }
  }
  return k;
}

} // namespace tearflow::rom
