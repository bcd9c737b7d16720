#include "run/flow_model.hpp"

#include <algorithm>
#include <span>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "core/names.hpp"
#include "core/units.hpp"
#include "fem/alike_on_every_rank.hpp"
#include "fem/petsc.hpp"
#include "mesh/merge.hpp"
#include "mesh/orient_faces.hpp"
#include "mesh/readers.hpp"
#include "mesh/region.hpp"
#include "run/run_fingerprint.hpp"
#include "run/startup.hpp"
#include "run/time_loop.hpp"

namespace tearflow::run {

namespace {

template <typename Problem> class StepperOf final : public FlowStepper {
public:
  StepperOf(Problem& problem, const physics::NewtonSpec& newton) : stepper_(problem, newton) {}
  Vec solution() const override { return stepper_.solution(); }
  Vec acceleration() const override { return stepper_.acceleration(); }
  physics::StepReport step(double t, double dt) override { return stepper_.step(t, dt); }
  bool uses_exact_operator() const override { return stepper_.uses_exact_operator(); }
  void use_exact_operator() override { stepper_.use_exact_operator(); }
  void rebuild_preconditioner_next() override { stepper_.rebuild_preconditioner_next(); }

private:
  physics::NewtonStepper<Problem> stepper_;
};

} // namespace

std::unique_ptr<FlowStepper> make_stepper(physics::FluidProblem& p, const physics::NewtonSpec& n) {
  return std::make_unique<StepperOf<physics::FluidProblem>>(p, n);
}

std::unique_ptr<FlowStepper> make_stepper(physics::FsiProblem& p, const physics::NewtonSpec& n) {
  return std::make_unique<StepperOf<physics::FsiProblem>>(p, n);
}

namespace {

/// The case's mesh made ready: the wall's file merged, the flow's region taken, faces oriented
/// and checked against the case's conditions. No collective call (load_mesh).
mesh::Mesh prepare_mesh(const io::Case& c, mesh::Mesh m) {
  if (!c.mesh.wall_file.empty())
    m = mesh::merge_fluid_and_wall(m, mesh::read_mesh(c.mesh.wall_file, c.mesh.length_scale));
  if (io::is_fsi(c)) { // both regions; the fluid's and the wall's faces
    for (const char* region : {"fluid", "wall"})
      if (std::find(m.regions.begin(), m.regions.end(), region) == m.regions.end())
        input_error("{}: a fluid-structure case needs volume regions 'fluid' and 'wall'; the "
                    "mesh{} has {}",
                    c.file.string(), m.source.empty() ? "" : " " + m.source,
                    join_names(m.regions, "and"));
    mesh::orient_faces_outward(m);
    io::check_case_against_mesh(c, m);
    io::check_solid_against_mesh(*c.solid, m, c.file.string());
    return m;
  }
  // The flow lives in one region: the named one, or `fluid` of a multi-region (FSI) mesh.
  if (!c.mesh.region.empty() || m.regions.size() > 1) {
    const std::string region = c.mesh.region.empty() ? "fluid" : c.mesh.region;
    if (c.mesh.region.empty() &&
        std::find(m.regions.begin(), m.regions.end(), region) == m.regions.end())
      input_error("{}: the mesh has {} volume regions and none is called 'fluid'; name the "
                  "flow's region with mesh.region",
                  m.source, m.regions.size());
    m = mesh::extract_region(m, region);
  }
  mesh::orient_faces_outward(m);
  io::check_case_against_mesh(c, m);
  return m;
}

} // namespace

mesh::Mesh load_mesh(const io::Case& c) {
  // Every rank reads and checks the mesh itself; a bad one stops all ranks with one message
  // (fem/alike_on_every_rank.hpp). The built-in model is built by rank 0 behind a barrier
  // (default_case.cpp), so its generator runs outside.
  if (c.mesh.generator)
    return fem::alike_on_every_rank(PETSC_COMM_WORLD, [&, m = c.mesh.generator(c)]() mutable {
      return prepare_mesh(c, std::move(m));
    });
  return fem::alike_on_every_rank(PETSC_COMM_WORLD, [&] {
    return prepare_mesh(c, c.mesh.pipe ? mesh::make_pipe(*c.mesh.pipe)
                                       : mesh::read_mesh(c.mesh.file, c.mesh.length_scale));
  });
}

bc::FluidConditions make_conditions(const io::Case& c, const mesh::Mesh& m) {
  bc::FluidConditions out;
  // A rigid-wall flow's faces without a condition are no-slip walls (docs/case-file.md). In
  // FSI the interface moves with the wall and the wall's own faces are the solid's.
  if (!io::is_fsi(c))
    for (const mesh::Face& f : m.faces)
      if (std::none_of(c.boundary_conditions.begin(), c.boundary_conditions.end(),
                       [&](const bc::BoundaryCondition& b) { return b.face == f.name; }))
        out.walls.push_back(f.name);
  for (const bc::BoundaryCondition& b : c.boundary_conditions) {
    if (std::holds_alternative<bc::NoSlip>(b.kind))
      out.walls.push_back(b.face);
    else if (const bc::Inflow* in = b.inflow())
      out.inflows.emplace_back(m, m.face(b.face), in->flow, in->profile, c.fluid.density,
                               c.fluid.viscosity, in->womersley_modes);
    else if (const bc::Outlet* o = b.outlet())
      out.outlets.push_back({b.face, o->law, o->backflow_beta});
  }
  return out;
}

physics::FluidProperties fluid_properties(const io::Case& c) {
  return c.fluid;
}

FlowModel::FlowModel(const io::Case& c, const mesh::Mesh& m, const fem::DistributedMesh& dmesh)
    : Model(c, m, dmesh) {
  problem_ = std::make_unique<physics::FluidProblem>(
      m, dmesh, fluid_properties(c), make_conditions(c, m),
      physics::GeneralizedAlpha::from_spectral_radius(c.time.spectral_radius));
  fluid_ = problem_.get();
  stepper_ = make_stepper(*problem_, c.newton);
  if (c.time.start_from_0d)
    start_from_0d();
}

FlowModel::~FlowModel() {
  stepper_.reset(); // before the problem it refers to (its preconditioner must outlive the KSP)
}

std::optional<double> FlowModel::start_from_0d() {
  physics::FluidProblem& problem = fluid();
  const std::optional<OutletModel> model = outlet_model(problem.conditions());
  if (!model)
    return std::nullopt;
  const bc::PeriodicState periodic = model->network.periodic(model->inflow);
  std::vector<physics::FluidProblem::OutletState> states = problem.outlet_states();
  std::string told;
  for (size_t i = 0; i < model->outlet.size(); ++i) {
    const bc::TractionOutlet& o = problem.conditions().outlets[model->outlet[i]];
    const double pd = periodic.distal_pressure(i, 0.0);
    if (std::optional<bc::OutletState> s = bc::start_state(o.law, pd)) { // else: the case's
      states[model->outlet[i]].law = *s;
      told += fmt::format(" {} {:.1f} mmHg", o.face, pd / units::mmHg);
    }
  }
  problem.set_outlet_states(states);
  // The pressure field starts at the 0D inlet pressure: a good first Newton guess, and with a
  // wall the state the wall is put in equilibrium with (below).
  const double p0 = periodic.inlet_pressure(0.0);
  {
    fem::WriteArray u(solution());
    for (Index l = 0; l < dmesh_.num_owned(); ++l)
      u[block() * l + 3] = p0;
  }
  start_notes_.push_back(fmt::format("start from the periodic 0D state at t = 0: pressure {:.1f} "
                                     "mmHg; distal pressures{}",
                                     p0 / units::mmHg, told.empty() ? " as given" : told));
  return p0;
}

fem::OwnedVec FlowModel::state_at_step_time() const {
  // The scheme's pressure is its stage value p_{n+af} (fluid_problem.hpp); with the change
  // over the last step the stepper keeps, p(t_{n+1}) = p_{n+af} + (1 - af) (p_{n+af} -
  // p_{n-1+af}), second order like the scheme. Before any step the change is 0 and the state
  // is the initial one.
  fem::OwnedVec state;
  TF_PETSC(VecDuplicate(solution(), state.out()));
  TF_PETSC(VecCopy(solution(), state));
  const double lag = 1.0 - fluid().scheme().alpha_f;
  const int bs = block(), slot = physics::NewtonStepper<physics::FluidProblem>::pressure_slot;
  fem::WriteArray u(state);
  fem::ReadArray change(derivative());
  PetscInt n = 0;
  TF_PETSC(VecGetLocalSize(state, &n));
  for (PetscInt i = slot; i < n; i += bs)
    u[i] += lag * change[i];
  return state;
}

StepSample FlowModel::sample() const {
  StepSample s{step(), time(), {}};
  const std::vector<physics::FluidProblem::OutletState> states = fluid().outlet_states();
  const auto& outlets = fluid().conditions().outlets;
  const fem::OwnedVec state = state_at_step_time();
  for (const physics::FaceMeasure& m : fluid().measure_faces(state)) {
    FaceSample f{m, std::nullopt};
    for (size_t i = 0; i < outlets.size(); ++i)
      if (outlets[i].face == m.face)
        f.distal_pressure = bc::distal_pressure(outlets[i].law, states[i].law);
    s.faces.push_back(f);
  }
  return s;
}

void FlowModel::begin_record() {
  std::vector<std::string> outlets;
  for (const bc::TractionOutlet& o : fluid().conditions().outlets)
    outlets.push_back(o.face);
  record_ = std::make_unique<RunRecord>(
      std::move(outlets), case_.time.steps_per_cycle, case_.time.period,
      case_.time.periodicity_measure == io::TimeSpec::Periodicity::pressures_and_splits);
}

std::vector<io::PointField> FlowModel::fields() const {
  const std::vector<double> U = gather(solution()), Udot = gather(derivative());
  const std::vector<double> aligned = gather(state_at_step_time());
  const std::vector<double> D = wall_state();
  if (fem::mpi_rank(dmesh_.comm()) != 0)
    return {};
  const int bs = block();
  // du/dt as the integrator holds it: with the frame before (one step earlier) it gives the
  // stage the step's equations held at, for the conservative flux (analysis/conservative_flux).
  io::PointField velocity{"velocity", 3, {}}, pressure{"pressure", 1, {}};
  io::PointField stage_pressure{"stage_pressure", 1, {}}, acceleration{"acceleration", 3, {}};
  io::PointField displacement{"displacement", 3, {}}, wall_pressure{"wall_pressure", 1, {}};
  velocity.values.reserve(3 * mesh_.points.size());
  for (Index n = 0; n < mesh_.num_nodes(); ++n) {
    for (int c = 0; c < 3; ++c) {
      velocity.values.push_back(U[bs * n + c]);
      acceleration.values.push_back(Udot[bs * n + c]);
    }
    pressure.values.push_back(aligned[bs * n + 3]);
    stage_pressure.values.push_back(U[bs * n + 3]);
    if (D.empty())
      continue;
    for (int c = 0; c < 3; ++c)
      displacement.values.push_back(D[bs * n + c]);
    wall_pressure.values.push_back(U[bs * n + physics::FsiProblem::wall_pressure]);
  }
  if (D.empty())
    return {velocity, pressure, acceleration, stage_pressure};
  // ParaView: "Warp By Vector" with displacement shows the deformed geometry.
  return {velocity, pressure, acceleration, displacement, wall_pressure, stage_pressure};
}

void FlowModel::report_cycle(const run::CycleStats& c, bool periodic) const {
  std::string faces;
  for (const run::FaceCycleStats& f : c.faces) {
    if (!f.split_percent)
      continue;
    faces +=
        fmt::format("  {}: {:.1f}/{:.1f} ({:.1f}) mmHg, {:.1f} %", f.face, f.systolic / units::mmHg,
                    f.diastolic / units::mmHg, f.mean / units::mmHg, *f.split_percent);
    const bc::TractionOutlet* o = nullptr;
    for (const bc::TractionOutlet& t : fluid().conditions().outlets)
      if (t.face == f.face)
        o = &t;
    if (o && f.reversed_volume > 1e-3 * std::abs(f.volume))
      faces += fmt::format(" (reversed {:.2g} mL{})", f.reversed_volume / units::mL,
                           o->backflow_beta == 0.0 ? ", no backflow stabilization" : "");
  }
  fmt::print("cycle {} (t = {:.4g}-{:.4g} s): change {}{}{}\n", c.cycle + 1, c.t_begin, c.t_end,
             c.change ? fmt::format("{:.2e}", *c.change) : std::string("-"),
             periodic ? " (periodic)" : "", faces);
}

int FlowModel::take_state(io::Checkpoint& c, const RunOptions& options) const {
  if (options.start_case.empty())
    return check_start(c, run_fingerprint(case_, mesh_), mesh_.num_nodes(), block(),
                       case_.time.step, case_.time.steps, options.start_from);
  const io::Case source = io::load_case(options.start_case);
  const mesh::Mesh source_mesh = load_mesh(source);
  const io::Fingerprint print = run_fingerprint(source, source_mesh);
  const int first = check_start(c, print, source_mesh.num_nodes(), block(), case_.time.step,
                                case_.time.steps, options.start_from);
  check_same_but_mesh(print, run_fingerprint(case_, mesh_), options.start_case);
  const fem::NodeTransfer transfer(source_mesh, mesh_);
  // Each pressure from its own region's tets; velocity and du/dt are continuous.
  const std::vector<std::string> unknowns = unknown_regions();
  c.solution = transfer.apply(c.solution, block(), unknowns);
  c.derivative = transfer.apply(c.derivative, block(), unknowns);
  const size_t outlets = outlet_record_size();
  const size_t source_wall = wall_state_size() > 0 ? source_mesh.num_nodes() * block() : 0;
  if (c.extra.size() != outlets + source_wall) // as set_extra's check, before interpolating
    input_error("checkpoint '{}' holds {} values beside the solution; its case needs {} (the "
                "states of {} outlets{})",
                options.start_from.string(), c.extra.size(), outlets + source_wall,
                fluid().conditions().outlets.size(),
                source_wall > 0 ? " and the displacement" : "");
  if (source_wall > 0) { // the displacement: continuous
    const std::vector<double> d = transfer.apply(
        std::vector<double>(c.extra.begin() + static_cast<std::ptrdiff_t>(outlets), c.extra.end()),
        block(), std::vector<std::string>(static_cast<size_t>(block()), ""));
    c.extra.resize(outlets);
    c.extra.insert(c.extra.end(), d.begin(), d.end());
  }
  if (fem::mpi_rank(dmesh_.comm()) == 0 && options.progress)
    spdlog::info("the state of {} nodes ('{}') interpolated to this mesh's {} (nodes outside "
                 "their region there: at most {:.3g} mm away)",
                 source_mesh.num_nodes(), source_mesh.source, mesh_.num_nodes(),
                 transfer.largest_distance() / units::mm);
  return first;
}

size_t FlowModel::outlet_record_size() const {
  size_t n = 0;
  for (const bc::TractionOutlet& o : fluid().conditions().outlets)
    n += bc::record_size(o.law) + 1;
  return n;
}

std::vector<double> FlowModel::extra() const {
  // Per outlet: its law's record (bc/outlet.hpp), then Q at t_n; then the wall's state.
  std::vector<double> extra;
  const std::vector<physics::FluidProblem::OutletState> states = fluid().outlet_states();
  for (size_t i = 0; i < states.size(); ++i) {
    bc::append_record(fluid().conditions().outlets[i].law, states[i].law, extra);
    extra.push_back(states[i].flux);
  }
  const std::vector<double> wall = wall_state();
  extra.insert(extra.end(), wall.begin(), wall.end());
  return extra;
}

void FlowModel::set_extra(const std::vector<double>& extra, const std::filesystem::path& file) {
  std::vector<physics::FluidProblem::OutletState> states = fluid().outlet_states();
  const size_t outlets = outlet_record_size(), wall = wall_state_size();
  if (extra.size() != outlets + wall)
    input_error("checkpoint '{}' holds {} values beside the solution; the case needs {} (the "
                "states of {} outlets{})",
                file.string(), extra.size(), outlets + wall, states.size(),
                wall > 0 ? " and the displacement" : "");
  const std::span<const double> all(extra);
  size_t at = 0;
  for (size_t i = 0; i < states.size(); ++i) {
    const bc::OutletLaw& law = fluid().conditions().outlets[i].law;
    const size_t n = bc::record_size(law);
    states[i] = {bc::restore(law, all.subspan(at, n)), all[at + n]};
    at += n + 1;
  }
  fluid().set_outlet_states(states);
  if (wall > 0)
    set_wall_state(
        std::vector<double>(extra.begin() + static_cast<std::ptrdiff_t>(at), extra.end()));
}

} // namespace tearflow::run
