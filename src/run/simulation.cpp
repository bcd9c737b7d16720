#include "run/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <span>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/file_layout.hpp"
#include "core/names.hpp"
#include "core/units.hpp"
#include "fem/node_transfer.hpp"
#include "io/checkpoint.hpp"
#include "io/vtu_series.hpp"
#include "mesh/merge.hpp"
#include "mesh/orient_faces.hpp"
#include "mesh/readers.hpp"
#include "mesh/region.hpp"
#include "physics/fsi_problem.hpp"
#include "run/run_fingerprint.hpp"
#include "run/solid_simulation.hpp"
#include "run/startup.hpp"

namespace tearflow::run {

mesh::Mesh load_mesh(const io::Case& c) {
  mesh::Mesh m = c.mesh.generator ? c.mesh.generator(c)
                 : c.mesh.pipe    ? mesh::make_pipe(*c.mesh.pipe)
                                  : mesh::read_mesh(c.mesh.file, c.mesh.length_scale);
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

struct Simulation::Output {
  std::filesystem::path dir;
  std::unique_ptr<io::VtuSeries> series;
};

Simulation::Simulation(io::Case c, MPI_Comm comm)
    : case_(std::move(c)), mesh_(load_mesh(case_)),
      options_(std::make_unique<fem::SolverOptions>(case_.petsc_options)) {
  const fem::SolverOptions::Scope options(*options_);
  dmesh_ = std::make_unique<fem::DistributedMesh>(mesh_, comm);
  const physics::FluidProperties fluid{case_.fluid.density, case_.fluid.viscosity,
                                       case_.fluid.stabilization_time_scale};
  const auto scheme = physics::GeneralizedAlpha::from_spectral_radius(case_.time.spectral_radius);
  if (io::is_fsi(case_)) {
    auto region = [&](const char* name) {
      return static_cast<int>(std::find(mesh_.regions.begin(), mesh_.regions.end(), name) -
                              mesh_.regions.begin());
    };
    fsi_ = std::make_unique<physics::FsiProblem>(
        mesh_, *dmesh_, fluid, make_conditions(case_, mesh_), case_.solid->material,
        case_.solid->conditions, scheme, physics::FsiRegions{region("fluid"), region("wall")});
    const double stiffness = fsi_->select_solver(case_.time.step);
    if (fem::mpi_rank(comm) == 0)
      spdlog::info("the wall's stiffness number (E / rho) dt^2 / h^2 = {:.3g}: its block by {}",
                   stiffness,
                   physics::FsiPreconditioner::wall_solved_directly(stiffness)
                       ? "MUMPS, a Jacobian every Newton iteration"
                       : "ILU(1) per rank, Newton keeping its Jacobian while it contracts");
    fsi_solver_ = std::make_unique<physics::FsiSolver>(*fsi_, case_.newton);
  } else {
    problem_ = std::make_unique<physics::FluidProblem>(mesh_, *dmesh_, fluid,
                                                       make_conditions(case_, mesh_), scheme);
    solver_ = std::make_unique<physics::FluidSolver>(*problem_, case_.newton);
  }
  if (case_.time.start_from_0d)
    start_from_0d();
}

physics::FluidProblem& Simulation::fluid() const {
  return fsi_ ? fsi_->fluid() : *problem_;
}

int Simulation::block() const {
  return fsi_ ? physics::FsiProblem::block : physics::FluidProblem::block;
}

Vec Simulation::solution() const {
  return fsi_ ? fsi_solver_->solution() : solver_->solution();
}

Vec Simulation::acceleration() const {
  return fsi_ ? fsi_solver_->acceleration() : solver_->acceleration();
}

void Simulation::start_from_0d() {
  physics::FluidProblem& problem = fluid();
  const std::optional<OutletModel> model = outlet_model(problem.conditions());
  if (!model)
    return;
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
    for (Index l = 0; l < dmesh_->num_owned(); ++l)
      u[block() * l + 3] = p0;
  }
  start_notes_.push_back(fmt::format("start from the periodic 0D state at t = 0: pressure {:.1f} "
                                     "mmHg; distal pressures{}",
                                     p0 / units::mmHg, told.empty() ? " as given" : told));
  if (fsi_)
    load_wall(p0);
}

void Simulation::load_wall(double p0) {
  // Without it the unloaded wall inflates in the first steps, drawing its stored volume
  // (about 10 mL at 46 mmHg in the 4.5 mm dissection) from the outlets' capacitors, whose
  // pressures then recover over several cycles (R_d C ~ 1.5 s): the wall is solved
  // quasi-statically under p0 on the fluid interface, with its own supports, first.
  if (std::none_of(mesh_.faces.begin(), mesh_.faces.end(),
                   [](const mesh::Face& f) { return f.name == "interface"; })) {
    if (fem::mpi_rank(dmesh_->comm()) == 0)
      spdlog::warn("the mesh names no fluid-wall face 'interface': the wall starts unloaded, "
                   "and its first steps inflate it");
    return;
  }
  io::Case wall_case = case_;
  wall_case.boundary_conditions.clear();
  wall_case.solid->quasi_static = true;
  wall_case.solid->conditions.loads.push_back({"interface", bc::Waveform::constant(p0)});
  wall_case.time.step = 1e3; // the tissue support's damping c_s du/dt then vanishes
  mesh::Mesh wall = mesh::extract_region(mesh_, "wall");
  mesh::orient_faces_outward(wall); // the interface's normal out of the wall: p0 inflates
  // One static solve of the thin wall: a direct one (the FSI's wall block is solved so too),
  // unless the options database says otherwise; the solid's default split stalls here.
  fem::set_default_options(
      {{"-solid_pc_type", "lu"}, {"-solid_pc_factor_mat_solver_type", "mumps"}});
  SolidSimulation solid(wall_case, wall, dmesh_->comm());
  const physics::StepReport r = solid.advance();
  const std::vector<double> d = solid.gather(solid.solver().displacement()),
                            v = solid.gather(solid.solver().solution());
  // The wall mesh keeps the FSI mesh's wall nodes in their order (mesh/region.hpp).
  const int region = static_cast<int>(
      std::find(mesh_.regions.begin(), mesh_.regions.end(), "wall") - mesh_.regions.begin());
  std::vector<char> in_wall(mesh_.num_nodes(), 0);
  for (size_t e = 0; e < mesh_.tets.size(); ++e)
    if (mesh_.tet_region[e] == region)
      for (Index n : mesh_.tets[e])
        in_wall[n] = 1;
  constexpr int bs = physics::FsiProblem::block, ws = physics::SolidProblem::block;
  std::vector<double> all(static_cast<size_t>(mesh_.num_nodes()) * bs, 0.0);
  std::vector<double> wall_pressure(mesh_.num_nodes(), 0.0);
  for (Index n = 0, j = 0; n < mesh_.num_nodes(); ++n)
    if (in_wall[n]) {
      for (int c = 0; c < 3; ++c)
        all[bs * n + c] = d[ws * j + c];
      wall_pressure[n] = v[ws * j + 3];
      ++j;
    }
  fsi_->set_wall_displacement(all);
  {
    fem::WriteArray u(solution());
    for (Index l = 0; l < dmesh_->num_owned(); ++l)
      u[bs * l + physics::FsiProblem::wall_pressure] = wall_pressure[dmesh_->original_index(l)];
  }
  double largest = 0.0;
  for (Index n = 0; n < mesh_.num_nodes(); ++n)
    largest =
        std::max(largest, std::sqrt(all[bs * n] * all[bs * n] + all[bs * n + 1] * all[bs * n + 1] +
                                    all[bs * n + 2] * all[bs * n + 2]));
  const double volume = fsi_->fluid_volume(); // (collective)
  start_notes_.push_back(fmt::format("wall loaded with {:.1f} mmHg on its fluid side: largest "
                                     "displacement {:.3g} mm ({} Newton iterations), fluid "
                                     "volume {:.2f} mL",
                                     p0 / units::mmHg, largest / units::mm, r.newton_iterations,
                                     volume / units::mL));
}

std::vector<std::string> Simulation::outlet_faces() const {
  std::vector<std::string> out;
  for (const bc::TractionOutlet& o : fluid().conditions().outlets)
    out.push_back(o.face);
  return out;
}

StepSample Simulation::sample() const {
  StepSample s{step_, time(), {}};
  const std::vector<physics::FluidProblem::OutletState> states = fluid().outlet_states();
  const auto& outlets = fluid().conditions().outlets;
  for (const physics::FaceMeasure& m : fluid().measure_faces(solution())) {
    FaceSample f{m, std::nullopt};
    for (size_t i = 0; i < outlets.size(); ++i)
      if (outlets[i].face == m.face)
        f.distal_pressure = bc::distal_pressure(outlets[i].law, states[i].law);
    s.faces.push_back(f);
  }
  return s;
}

void Simulation::set_outlets(const std::vector<bc::WindkesselBranch>& outlets) {
  physics::FluidProblem& problem = fluid();
  const auto& specs = problem.conditions().outlets;
  for (const bc::WindkesselBranch& w : outlets) {
    const auto it = std::find_if(specs.begin(), specs.end(),
                                 [&](const bc::TractionOutlet& o) { return o.face == w.name; });
    const bc::RcrOutlet* old = it == specs.end() ? nullptr : std::get_if<bc::RcrOutlet>(&it->law);
    if (!old)
      throw std::logic_error("set_outlets: '" + w.name + "' is no RCR outlet of the case");
    bc::RcrOutlet tuned = *old;
    tuned.rcr = w.rcr;
    tuned.rcr.reference_pressure = old->rcr.reference_pressure;
    problem.set_outlet_law(static_cast<size_t>(it - specs.begin()), tuned);
    for (bc::BoundaryCondition& b : case_.boundary_conditions)
      if (b.face == w.name)
        b.outlet()->law = tuned;
  }
}

Simulation::~Simulation() = default;

physics::StepReport Simulation::advance() {
  const fem::SolverOptions::Scope options(*options_);
  physics::StepReport r =
      fsi_ ? fsi_solver_->step(time(), case_.time.step) : solver_->step(time(), case_.time.step);
  ++step_;
  return r;
}

std::vector<double> Simulation::gather(Vec v) const {
  VecScatter to_all;
  Vec all;
  TF_PETSC(VecScatterCreateToAll(v, &to_all, &all));
  TF_PETSC(VecScatterBegin(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD));
  TF_PETSC(VecScatterEnd(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD));
  const int bs = block();
  std::vector<double> out(static_cast<size_t>(mesh_.num_nodes()) * bs);
  {
    fem::ReadArray a(all);
    const auto& o2g = dmesh_->original_to_global();
    for (Index n = 0; n < mesh_.num_nodes(); ++n)
      for (int c = 0; c < bs; ++c)
        out[bs * n + c] = a[bs * o2g[n] + c];
  }
  VecScatterDestroy(&to_all);
  VecDestroy(&all);
  return out;
}

void Simulation::set_state(int step, const std::vector<double>& U,
                           const std::vector<double>& Udot) {
  const int bs = block();
  fem::WriteArray u(solution()), ud(acceleration());
  for (Index l = 0; l < dmesh_->num_owned(); ++l) {
    const Index n = dmesh_->original_index(l);
    for (int c = 0; c < bs; ++c) {
      u[bs * l + c] = U[bs * n + c];
      ud[bs * l + c] = Udot[bs * n + c];
    }
  }
  step_ = step;
}

void Simulation::write_frame() {
  const std::vector<double> U = gather(solution()), Udot = gather(acceleration());
  const std::vector<double> D = fsi_ ? gather(fsi_->displacement()) : std::vector<double>{};
  if (fem::mpi_rank(dmesh_->comm()) != 0)
    return;
  const int bs = block();
  // du/dt as the integrator holds it: with the frame before (one step earlier) it gives the
  // stage the step's equations held at, for the conservative flux (analysis/conservative_flux).
  io::PointField velocity{"velocity", 3, {}}, pressure{"pressure", 1, {}};
  io::PointField acceleration{"acceleration", 3, {}};
  io::PointField displacement{"displacement", 3, {}}, wall_pressure{"wall_pressure", 1, {}};
  velocity.values.reserve(3 * mesh_.points.size());
  for (Index n = 0; n < mesh_.num_nodes(); ++n) {
    for (int c = 0; c < 3; ++c) {
      velocity.values.push_back(U[bs * n + c]);
      acceleration.values.push_back(Udot[bs * n + c]);
    }
    pressure.values.push_back(U[bs * n + 3]);
    if (!fsi_)
      continue;
    for (int c = 0; c < 3; ++c)
      displacement.values.push_back(D[bs * n + c]);
    wall_pressure.values.push_back(U[bs * n + physics::FsiProblem::wall_pressure]);
  }
  if (fsi_) // ParaView: "Warp By Vector" with displacement shows the deformed geometry
    output_->series->write(step_, time(),
                           {velocity, pressure, acceleration, displacement, wall_pressure});
  else
    output_->series->write(step_, time(), {velocity, pressure, acceleration});
}

RunSummary Simulation::run(const RunOptions& options) {
  const fem::SolverOptions::Scope solver_options(*options_);
  const bool root = fem::mpi_rank(dmesh_->comm()) == 0;
  output_ = std::make_unique<Output>();
  output_->dir = case_.output.directory;
  const std::filesystem::path checkpoint_file = RunFiles{output_->dir}.checkpoint();
  const std::filesystem::path faces_csv = RunFiles{output_->dir}.faces_csv();
  const std::filesystem::path cycles_json = RunFiles{output_->dir}.cycles_json();
  if (root && options.write_output) {
    std::filesystem::create_directories(output_->dir);
    output_->series = std::make_unique<io::VtuSeries>(mesh_, output_->dir, "flow");
  }
  RunRecord record(outlet_faces(), case_.time.steps_per_cycle, case_.time.period,
                   case_.time.periodicity_measure ==
                       io::TimeSpec::Periodicity::pressures_and_splits);

  if (options.restart) {
    const io::Checkpoint c = io::read_checkpoint(checkpoint_file);
    check_restart(c, run_fingerprint(case_, mesh_), mesh_.num_nodes(), block(), case_.time.steps,
                  checkpoint_file);
    set_state(static_cast<int>(c.step), c.solution, c.derivative);
    set_outlet_checkpoint(c.extra, checkpoint_file);
    if (c.exact_operator) // the method the run had switched to (fluid_solver.cpp)
      fsi_ ? fsi_solver_->use_exact_operator() : solver_->use_exact_operator();
    if (options.write_output) {
      record.load_csv(faces_csv, step_); // every rank: all must agree on periodicity
      if (root) {
        io::write_file_atomically(faces_csv, record.csv()); // without rows after the checkpoint
        output_->series->load_existing(case_.time.step);
        output_->series->truncate_after(time());
      }
    }
    if (root && options.progress)
      fmt::print("restarting from step {} (t = {:.6g} s) of '{}'{}\n", step_, time(),
                 checkpoint_file.string(), c.exact_operator ? ", with the exact operator" : "");
  } else {
    if (!options.start_from.empty()) {
      io::Checkpoint c = io::read_checkpoint(options.start_from);
      const int first =
          options.start_case.empty()
              ? check_start(c, run_fingerprint(case_, mesh_), mesh_.num_nodes(), block(),
                            case_.time.step, case_.time.steps, options.start_from)
              : take_state_of_mesh(c, options);
      set_state(first, c.solution, c.derivative);
      set_outlet_checkpoint(c.extra, options.start_from);
      // Not the exact operator the run may have switched to: that was its step's need; at
      // another step Newton falls back to it again if it must (fluid_solver.cpp).
      if (root && options.progress)
        spdlog::info("start from the state at t = {:.6g} s of '{}' (its step {} s, now {} s)",
                     time(), options.start_from.string(), c.time_step, case_.time.step);
    } else if (root && options.progress)
      for (const std::string& note : start_notes_)
        spdlog::info("{}", note);
    if (options.write_output)
      write_frame();
    record.add(sample());
    if (root && options.write_output) // then a row per step as the run goes
      io::write_file_atomically(faces_csv, record.csv());
  }

  auto write_record = [&] {
    if (!root || !options.write_output)
      return;
    io::write_file_atomically(faces_csv, record.csv());
    if (case_.time.steps_per_cycle > 0)
      io::write_file_atomically(cycles_json, record.cycles_json().dump(2) + "\n");
  };
  auto write_checkpoint = [&] {
    io::Checkpoint c;
    c.step = step_;
    c.time = time();
    c.time_step = case_.time.step;
    c.num_nodes = mesh_.num_nodes();
    c.block = block();
    c.fingerprint = run_fingerprint(case_, mesh_); // the outlets as they run now
    c.solution = gather(solution());
    c.derivative = gather(acceleration());
    c.extra = outlet_checkpoint();
    c.exact_operator = fsi_ ? fsi_solver_->uses_exact_operator() : solver_->uses_exact_operator();
    if (root)
      io::write_checkpoint(checkpoint_file, c);
    // A restart from here builds its preconditioner afresh: so does the run going on.
    fsi_ ? fsi_solver_->rebuild_preconditioner_next() : solver_->rebuild_preconditioner_next();
  };

  RunSummary summary;
  const double start = MPI_Wtime();
  const int total = case_.time.steps;
  bool periodic = false;
  while (step_ < total && !periodic) {
    physics::StepReport r;
    try {
      r = advance();
    } catch (const SolverError& e) {
      write_record();
      throw SolverError(fmt::format("{} (step {}). {}", e.what(), step_ + 1,
                                    case_.output.checkpoint_every > 0 && options.write_output &&
                                            std::filesystem::exists(checkpoint_file)
                                        ? "The last good checkpoint is kept in '" +
                                              checkpoint_file.string() + "'."
                                        : "No checkpoint was written."),
                        e.collective);
    }
    summary.reports.push_back(r);
    ++summary.steps;
    std::optional<run::CycleStats> cycle = record.add(sample());
    if (root && options.write_output) // a killed run keeps every step it finished
      io::append_to_file(faces_csv, RunRecord::csv_rows(record.samples().back()));
    if (cycle) {
      periodic = case_.time.periodicity_tolerance > 0.0 && cycle->change &&
                 *cycle->change < case_.time.periodicity_tolerance;
      if (root && options.progress)
        report_cycle(*cycle, periodic);
      if (options.on_cycle)
        periodic = options.on_cycle(*cycle, periodic); // "periodic" now: the run stops
    }
    if (options.write_output) {
      const bool last = step_ == total || periodic;
      if ((case_.output.every > 0 && step_ % case_.output.every == 0) || last)
        write_frame();
      if (case_.output.checkpoint_every > 0 &&
          (step_ % case_.output.checkpoint_every == 0 || last)) {
        write_record();
        write_checkpoint();
      }
    }
    if (root && options.progress) {
      const double elapsed = MPI_Wtime() - start;
      const double eta = elapsed / summary.steps * (total - step_);
      // The solve that counted, and apart what a failed attempt spent before it.
      const std::string newton =
          r.retried_iterations > 0
              ? fmt::format("{} (+{} retried)", r.newton_iterations - r.retried_iterations,
                            r.retried_iterations)
              : fmt::format("{}", r.newton_iterations);
      fmt::print("step {:>5}/{}  t = {:.5f} s  Newton {} (|R| {:.2e} -> {:.2e}, Jacobians {})  "
                 "KSP {:>4}  {:.2f} s/step (assembly {:.2f} s)  ETA {:.0f} s\n",
                 step_, total, time(), newton, r.residual_initial, r.residual_final, r.jacobians,
                 r.linear_iterations, r.assembly_seconds + r.solve_seconds, r.assembly_seconds,
                 eta);
      std::fflush(stdout);
    }
  }
  write_record();
  if (case_.time.periodicity_tolerance > 0.0 && !periodic && root)
    spdlog::warn("not periodic within {} after {} cycle(s) ({}); raise "
                 "time.periodicity.max_cycles to continue with --restart",
                 case_.time.periodicity_tolerance, record.cycles().size(),
                 record.cycles().empty() || !record.cycles().back().change
                     ? std::string("no two complete cycles to compare")
                     : fmt::format("last change {:.3g}", *record.cycles().back().change));
  summary.wall_seconds = MPI_Wtime() - start;
  summary.periodic = periodic;
  summary.cycles = record.cycles();
  return summary;
}

void Simulation::report_cycle(const run::CycleStats& c, bool periodic) const {
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

int Simulation::take_state_of_mesh(io::Checkpoint& c, const RunOptions& options) const {
  const io::Case source = io::load_case(options.start_case);
  const mesh::Mesh source_mesh = load_mesh(source);
  const io::Fingerprint print = run_fingerprint(source, source_mesh);
  const int first = check_start(c, print, source_mesh.num_nodes(), block(), case_.time.step,
                                case_.time.steps, options.start_from);
  check_same_but_mesh(print, run_fingerprint(case_, mesh_), options.start_case);
  const fem::NodeTransfer transfer(source_mesh, mesh_);
  // Each pressure from its own region's tets; velocity and du/dt are continuous.
  const std::vector<std::string> unknowns =
      fsi_ ? std::vector<std::string>{"", "", "", "fluid", "wall"}
           : std::vector<std::string>{"", "", "", ""};
  c.solution = transfer.apply(c.solution, block(), unknowns);
  c.derivative = transfer.apply(c.derivative, block(), unknowns);
  const size_t outlets = outlet_record_size();
  if (fsi_ && c.extra.size() > outlets) { // the displacement: continuous
    const std::vector<double> d = transfer.apply(
        std::vector<double>(c.extra.begin() + static_cast<std::ptrdiff_t>(outlets), c.extra.end()),
        block(), std::vector<std::string>(static_cast<size_t>(block()), ""));
    c.extra.resize(outlets);
    c.extra.insert(c.extra.end(), d.begin(), d.end());
  }
  if (fem::mpi_rank(dmesh_->comm()) == 0 && options.progress)
    spdlog::info("the state of {} nodes ('{}') interpolated to this mesh's {} (nodes outside "
                 "their region there: at most {:.3g} mm away)",
                 source_mesh.num_nodes(), source_mesh.source, mesh_.num_nodes(),
                 transfer.largest_distance() / units::mm);
  return first;
}

size_t Simulation::outlet_record_size() const {
  size_t n = 0;
  for (const bc::TractionOutlet& o : fluid().conditions().outlets)
    n += bc::record_size(o.law) + 1;
  return n;
}

std::vector<double> Simulation::outlet_checkpoint() const {
  // Per outlet: its law's record (bc/outlet.hpp), then Q at t_n.
  std::vector<double> extra;
  const std::vector<physics::FluidProblem::OutletState> states = fluid().outlet_states();
  for (size_t i = 0; i < states.size(); ++i) {
    bc::append_record(fluid().conditions().outlets[i].law, states[i].law, extra);
    extra.push_back(states[i].flux);
  }
  if (fsi_) { // then the displacement of every node, as the solution
    const std::vector<double> D = gather(fsi_->displacement());
    extra.insert(extra.end(), D.begin(), D.end());
  }
  return extra;
}

void Simulation::set_outlet_checkpoint(const std::vector<double>& extra,
                                       const std::filesystem::path& file) {
  std::vector<physics::FluidProblem::OutletState> states = fluid().outlet_states();
  const size_t displacement = fsi_ ? static_cast<size_t>(mesh_.num_nodes()) * block() : 0;
  const size_t outlets = outlet_record_size();
  if (extra.size() != outlets + displacement)
    input_error("checkpoint '{}' holds {} values beside the solution; the case needs {} (the "
                "states of {} outlets{})",
                file.string(), extra.size(), outlets + displacement, states.size(),
                fsi_ ? " and the displacement" : "");
  const std::span<const double> all(extra);
  size_t at = 0;
  for (size_t i = 0; i < states.size(); ++i) {
    const bc::OutletLaw& law = fluid().conditions().outlets[i].law;
    const size_t n = bc::record_size(law);
    states[i] = {bc::restore(law, all.subspan(at, n)), all[at + n]};
    at += n + 1;
  }
  fluid().set_outlet_states(states);
  if (fsi_)
    fsi_->set_displacement(
        std::vector<double>(extra.begin() + static_cast<std::ptrdiff_t>(at), extra.end()));
}

} // namespace tearflow::run
