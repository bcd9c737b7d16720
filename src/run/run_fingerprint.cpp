#include "run/run_fingerprint.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tearflow::run {

namespace {

std::string condition(const bc::BoundaryCondition& b) {
  if (const bc::Inflow* in = b.inflow())
    return fmt::format("inflow {} (profile {}, {} modes)", bc::describe(in->flow),
                       static_cast<int>(in->profile), in->womersley_modes);
  if (const bc::Outlet* o = b.outlet())
    return fmt::format("{}, backflow {}", bc::describe(o->law), o->backflow_beta);
  return "no_slip";
}

} // namespace

io::Fingerprint run_fingerprint(const io::Case& c, const mesh::Mesh& m) {
  io::Fingerprint f;
  f.emplace_back("mesh", fmt::format("{} nodes, {} tets, {} regions, digest {:016x}", m.num_nodes(),
                                     m.tets.size(), m.regions.size(), mesh::solution_digest(m)));
  f.emplace_back("time step", fmt::format("{} s", c.time.step));
  f.emplace_back("time scheme", fmt::format("spectral radius {}", c.time.spectral_radius));
  if (!c.boundary_conditions.empty())
    f.emplace_back("fluid", fmt::format("density {} kg/m^3, viscosity {} Pa s", c.fluid.density,
                                        c.fluid.viscosity));
  if (!c.boundary_conditions.empty()) {
    const physics::StabilizationSpec& s = c.fluid.stabilization;
    f.emplace_back("stabilization time scale", s.time_scale > 0.0
                                                   ? fmt::format("{} s", s.time_scale)
                                               : s.time_scale == 0.0 ? std::string("the step")
                                                                     : std::string("automatic"));
    f.emplace_back("stabilization",
                   fmt::format("metric {}, grad-div {}, viscous correction {}",
                               s.metric == physics::StabilizationSpec::Metric::symmetric
                                   ? "symmetric"
                                   : "reference_tet",
                               s.grad_div, s.viscous_correction ? "on" : "off"));
  }
  for (const bc::BoundaryCondition& b : c.boundary_conditions)
    f.emplace_back("face " + b.face, condition(b));
  if (c.solid) {
    const physics::SolidMaterial& s = c.solid->material;
    f.emplace_back("wall",
                   fmt::format("model {}, density {}, mu {}, kappa {}, "
                               "stabilization {}, {}",
                               static_cast<int>(s.model), s.density, s.mu, s.kappa, s.stabilization,
                               c.solid->quasi_static ? "quasi-static" : "dynamic"));
    for (const bc::FixedFace& x : c.solid->conditions.fixed)
      f.emplace_back("wall face " + x.face,
                     fmt::format("fixed {:03b} at ({}, {}, {}) m over {} s", x.components,
                                 x.displacement[0], x.displacement[1], x.displacement[2], x.ramp));
    for (const bc::PressureLoad& x : c.solid->conditions.loads)
      f.emplace_back("wall face " + x.face, "pressure " + bc::describe(x.pressure));
    for (const bc::RobinSupport& x : c.solid->conditions.supports)
      f.emplace_back("wall face " + x.face, fmt::format("support k {} Pa/m, c {} Pa s/m, p_0 {} Pa",
                                                        x.stiffness, x.damping, x.pressure));
  }
  return f;
}

namespace {

/// What a new run may change in a state it starts from (--start-from): how the same physics
/// is discretized in time, not the physics.
const std::set<std::string> kDiscretization = {"time step", "stabilization time scale"};

/// kDiscretization and the mesh: what --start-from --start-case may change.
std::set<std::string> discretization_and_mesh() {
  std::set<std::string> parts = kDiscretization;
  parts.insert("mesh");
  return parts;
}

/// "" when the checkpoint's parts equal `now`'s (parts named in `skip` aside), else a line
/// per part that changed.
std::string changes(const io::Fingerprint& then_parts, const io::Fingerprint& now,
                    const std::set<std::string>& skip) {
  const std::map<std::string, std::string> then(then_parts.begin(), then_parts.end());
  const std::map<std::string, std::string> current(now.begin(), now.end());
  std::string changed;
  for (const auto& [part, value] : current) {
    const auto it = then.find(part);
    if (skip.contains(part))
      continue;
    if (it == then.end())
      changed += fmt::format("\n  {}: not in the checkpoint; now {}", part, value);
    else if (it->second != value)
      changed += fmt::format("\n  {}: {} in the checkpoint; now {}", part, it->second, value);
  }
  for (const auto& [part, value] : then)
    if (!skip.contains(part) && !current.contains(part))
      changed += fmt::format("\n  {}: {} in the checkpoint; not in the case now", part, value);
  return changed;
}

void check_size(const io::Checkpoint& checkpoint, Index num_nodes, int block,
                const std::filesystem::path& file) {
  if (checkpoint.num_nodes != num_nodes || checkpoint.block != block)
    input_error("checkpoint '{}' has {} nodes x {} unknowns, the case's mesh {} x {}",
                file.string(), checkpoint.num_nodes, checkpoint.block, num_nodes, block);
}

} // namespace

void check_restart(const io::Checkpoint& checkpoint, const io::Fingerprint& now, Index num_nodes,
                   int block, int last_step, const std::filesystem::path& file) {
  // What changed first: another case's run in the folder (another mesh) is said as such, with
  // every part that differs, not as a node count that does not match.
  if (const std::string changed = changes(checkpoint.fingerprint, now, {}); !changed.empty()) {
    // Only the discretization in time changed: the state itself can start a run with it.
    const bool step_only = changes(checkpoint.fingerprint, now, kDiscretization).empty();
    input_error("checkpoint '{}' was written by a different run; what changed since:{}\nA "
                "restart continues the same run; {}",
                file.string(), changed,
                step_only ? fmt::format("to go on from its state at the new step, start a new run "
                                        "from it: --start-from {} -o ANOTHER_FOLDER",
                                        file.string())
                          : "run the changed case from the start (without --restart), into "
                            "another output folder to keep this one");
  }
  check_size(checkpoint, num_nodes, block, file);
  if (checkpoint.step > last_step)
    input_error("checkpoint '{}' is at step {} (t = {:.6g} s), past the case's last step {}: "
                "nothing to continue (raise the case's time.steps, end or cycles)",
                file.string(), checkpoint.step, checkpoint.time, last_step);
}

int check_start(const io::Checkpoint& checkpoint, const io::Fingerprint& now, Index num_nodes,
                int block, double time_step, int last_step, const std::filesystem::path& file) {
  if (const std::string changed = changes(checkpoint.fingerprint, now, kDiscretization);
      !changed.empty()) {
    const bool mesh_only = changes(checkpoint.fingerprint, now, discretization_and_mesh()).empty();
    input_error("checkpoint '{}' is the state of a different case; what differs:{}\n{}",
                file.string(), changed,
                mesh_only ? "A state on another mesh of the same case is interpolated to this "
                            "mesh when --start-case names the case of the run that wrote it"
                          : "--start-from takes the state of the same case (its time step and "
                            "stabilization time scale aside)");
  }
  check_size(checkpoint, num_nodes, block, file);
  const double steps = checkpoint.time / time_step;
  const int step = static_cast<int>(std::lround(steps));
  if (std::abs(steps - step) > 1e-9 * std::max(1.0, steps))
    input_error("checkpoint '{}' is at t = {:.9g} s, not a whole number of the case's steps of "
                "{} s: start from a checkpoint at such a time (a cycle's end)",
                file.string(), checkpoint.time, time_step);
  if (step >= last_step)
    input_error("checkpoint '{}' is at t = {:.6g} s, step {} of {} s, not before the case's last "
                "step {}: nothing to run (raise the case's time.steps, end or cycles)",
                file.string(), checkpoint.time, step, time_step, last_step);
  return step;
}

void check_same_but_mesh(const io::Fingerprint& source, const io::Fingerprint& now,
                         const std::filesystem::path& source_case) {
  if (const std::string changed = changes(source, now, discretization_and_mesh()); !changed.empty())
    input_error("case '{}' (the state's) differs from this case in more than the mesh, the "
                "time step and the stabilization time scale:{}",
                source_case.string(), changed);
}

} // namespace tearflow::run
