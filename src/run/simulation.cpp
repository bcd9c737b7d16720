#include "run/simulation.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "io/checkpoint.hpp"
#include "io/vtu_series.hpp"
#include "mesh/orient_faces.hpp"
#include "mesh/readers.hpp"

namespace tearflow::run {

mesh::Mesh load_mesh(const io::Case& c) {
  mesh::Mesh m = c.mesh.pipe ? mesh::make_pipe(*c.mesh.pipe)
                             : mesh::read_mesh(c.mesh.file, c.mesh.length_scale);
  mesh::orient_faces_outward(m);
  io::check_case_against_mesh(c, m);
  return m;
}

bc::FluidConditions make_conditions(const io::Case& c, const mesh::Mesh& m) {
  bc::FluidConditions out;
  for (const io::BoundaryCondition& b : c.boundary_conditions) {
    switch (b.type) {
    case io::BcType::NoSlip:
      out.walls.push_back(b.face);
      break;
    case io::BcType::Inflow: {
      const bc::ProfileShape shape = b.profile == io::InflowProfile::Plug ? bc::ProfileShape::Plug
                                     : b.profile == io::InflowProfile::Womersley
                                         ? bc::ProfileShape::Womersley
                                         : bc::ProfileShape::Parabolic;
      out.inflows.emplace_back(m, m.face(b.face), b.flow, shape, c.fluid.density, c.fluid.viscosity,
                               b.womersley_modes);
      break;
    }
    case io::BcType::Pressure:
      out.outlets.push_back({b.face, b.pressure, 0.0, b.backflow_beta});
      break;
    case io::BcType::Resistance:
      out.outlets.push_back({b.face, bc::Waveform::constant(0.0), b.resistance, b.backflow_beta});
      break;
    }
  }
  return out;
}

struct Simulation::Output {
  std::filesystem::path dir;
  std::unique_ptr<io::VtuSeries> series;
  std::vector<std::string> face_rows; ///< faces.csv body, one row per face and step
};

Simulation::Simulation(io::Case c, MPI_Comm comm) : case_(std::move(c)), mesh_(load_mesh(case_)) {
  dmesh_ = std::make_unique<fem::DistributedMesh>(mesh_, comm);
  problem_ = std::make_unique<physics::FluidProblem>(
      mesh_, *dmesh_, physics::FluidProperties{case_.fluid.density, case_.fluid.viscosity},
      make_conditions(case_, mesh_),
      physics::GeneralizedAlpha::from_spectral_radius(case_.time.spectral_radius));
  solver_ = std::make_unique<physics::FluidSolver>(*problem_, case_.newton);
}

Simulation::~Simulation() = default;

physics::StepReport Simulation::advance() {
  physics::StepReport r = solver_->step(time(), case_.time.step);
  ++step_;
  return r;
}

std::vector<double> Simulation::gather(Vec v) const {
  VecScatter to_all;
  Vec all;
  TF_PETSC(VecScatterCreateToAll(v, &to_all, &all));
  TF_PETSC(VecScatterBegin(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD));
  TF_PETSC(VecScatterEnd(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD));
  const int bs = physics::FluidProblem::block;
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
  const int bs = physics::FluidProblem::block;
  fem::WriteArray u(solver_->solution()), ud(solver_->acceleration());
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
  const std::vector<double> U = gather(solver_->solution());
  if (fem::mpi_rank(dmesh_->comm()) != 0)
    return;
  io::PointField velocity{"velocity", 3, {}}, pressure{"pressure", 1, {}};
  velocity.values.reserve(3 * mesh_.points.size());
  for (Index n = 0; n < mesh_.num_nodes(); ++n) {
    for (int c = 0; c < 3; ++c)
      velocity.values.push_back(U[4 * n + c]);
    pressure.values.push_back(U[4 * n + 3]);
  }
  output_->series->write(step_, time(), {velocity, pressure});
}

void Simulation::append_face_rows(std::vector<std::string>& rows) const {
  for (const physics::FaceMeasure& f : problem_->measure_faces(solver_->solution()))
    rows.push_back(fmt::format("{},{:.10g},{},{:.10e},{:.10e},{:.10e}", step_, time(), f.face,
                               f.flow, f.pressure, f.area));
}

RunSummary Simulation::run(const RunOptions& options) {
  const bool root = fem::mpi_rank(dmesh_->comm()) == 0;
  output_ = std::make_unique<Output>();
  output_->dir = case_.output.directory;
  const std::filesystem::path checkpoint_file = output_->dir / "checkpoint.bin";
  const std::filesystem::path faces_csv = output_->dir / "faces.csv";
  const std::string faces_header = "step,time_s,face,flow_m3_per_s,pressure_Pa,area_m2";
  if (root && options.write_output) {
    std::filesystem::create_directories(output_->dir);
    output_->series = std::make_unique<io::VtuSeries>(mesh_, output_->dir, "flow");
  }

  if (options.restart) {
    const io::Checkpoint c = io::read_checkpoint(checkpoint_file);
    if (c.num_nodes != mesh_.num_nodes() || c.block != physics::FluidProblem::block)
      input_error("checkpoint '{}' has {} nodes x {} unknowns, the case's mesh {} x {}",
                  checkpoint_file.string(), c.num_nodes, c.block, mesh_.num_nodes(),
                  physics::FluidProblem::block);
    set_state(static_cast<int>(c.step), c.solution, c.derivative);
    if (root && options.write_output) {
      output_->series->load_existing();
      output_->series->truncate_after(time());
      std::ifstream in(faces_csv);
      std::string line;
      std::getline(in, line); // header
      while (std::getline(in, line))
        if (std::stoi(line.substr(0, line.find(','))) <= step_)
          output_->face_rows.push_back(line);
    }
    if (root && options.progress)
      fmt::print("restarting from step {} (t = {:.6g} s) of '{}'\n", step_, time(),
                 checkpoint_file.string());
  } else if (options.write_output) {
    write_frame();
    append_face_rows(output_->face_rows);
  }

  auto write_faces_csv = [&] {
    if (!root || !options.write_output)
      return;
    std::string text = faces_header + "\n";
    for (const std::string& r : output_->face_rows)
      text += r + "\n";
    io::write_file_atomically(faces_csv, text);
  };
  auto write_checkpoint = [&] {
    io::Checkpoint c;
    c.step = step_;
    c.time = time();
    c.num_nodes = mesh_.num_nodes();
    c.block = physics::FluidProblem::block;
    c.solution = gather(solver_->solution());
    c.derivative = gather(solver_->acceleration());
    if (root)
      io::write_checkpoint(checkpoint_file, c);
  };

  RunSummary summary;
  const double start = MPI_Wtime();
  const int total = case_.time.steps;
  while (step_ < total) {
    physics::StepReport r;
    try {
      r = advance();
    } catch (const SolverError& e) {
      write_faces_csv();
      throw SolverError(fmt::format("{} (step {}). {}", e.what(), step_ + 1,
                                    case_.output.checkpoint_every > 0 && options.write_output
                                        ? "The last good checkpoint is kept in '" +
                                              checkpoint_file.string() + "'."
                                        : "No checkpoint was written."));
    }
    summary.reports.push_back(r);
    ++summary.steps;
    if (options.write_output) {
      append_face_rows(output_->face_rows);
      const bool last = step_ == total;
      if ((case_.output.every > 0 && step_ % case_.output.every == 0) || last)
        write_frame();
      if (case_.output.checkpoint_every > 0 &&
          (step_ % case_.output.checkpoint_every == 0 || last)) {
        write_faces_csv();
        write_checkpoint();
      }
    }
    if (root && options.progress) {
      const double elapsed = MPI_Wtime() - start;
      const double eta = elapsed / summary.steps * (total - step_);
      fmt::print("step {:>5}/{}  t = {:.5f} s  Newton {} (|R| {:.2e} -> {:.2e})  KSP {:>4}  "
                 "{:.2f} s/step (assembly {:.2f} s)  ETA {:.0f} s\n",
                 step_, total, time(), r.newton_iterations, r.residual_initial, r.residual_final,
                 r.linear_iterations, r.assembly_seconds + r.solve_seconds, r.assembly_seconds,
                 eta);
      std::fflush(stdout);
    }
  }
  write_faces_csv();
  summary.wall_seconds = MPI_Wtime() - start;
  return summary;
}

} // namespace tearflow::run
