#include "run/solid_simulation.hpp"

#include "core/file_layout.hpp"

#include <fstream>

#include <fmt/format.h>

#include "io/checkpoint.hpp"
#include "io/vtu_series.hpp"
#include "mesh/orient_faces.hpp"
#include "mesh/readers.hpp"
#include "run/run_fingerprint.hpp"

namespace tearflow::run {

namespace {
constexpr int block = physics::SolidProblem::block;

std::string source_of(const io::Case& c) {
  return c.file.empty() ? fmt::format("case '{}'", c.name) : c.file.string();
}
} // namespace

mesh::Mesh load_solid_mesh(const io::Case& c) {
  mesh::Mesh m = c.mesh.pipe ? mesh::make_pipe(*c.mesh.pipe)
                             : mesh::read_mesh(c.mesh.file, c.mesh.length_scale);
  mesh::orient_faces_outward(m);
  return m;
}

struct SolidSimulation::Output {
  std::filesystem::path dir;
  std::unique_ptr<io::VtuSeries> series;
  std::vector<std::string> face_rows; ///< faces.csv body, one row per face and step
};

SolidSimulation::SolidSimulation(io::Case c, MPI_Comm comm)
    : SolidSimulation(c, load_solid_mesh(c), comm) {}

SolidSimulation::SolidSimulation(io::Case c, mesh::Mesh m, MPI_Comm comm)
    : case_(std::move(c)), mesh_(std::move(m)),
      options_(std::make_unique<fem::SolverOptions>(case_.petsc_options)) {
  const fem::SolverOptions::Scope options(*options_);
  if (!case_.solid)
    input_error("{}: a solid simulation needs a `solid:` section", source_of(case_));
  const io::SolidSpec& s = *case_.solid;
  io::check_solid_against_mesh(s, mesh_, source_of(case_));
  dmesh_ = std::make_unique<fem::DistributedMesh>(mesh_, comm);
  const physics::SolidScheme scheme =
      s.quasi_static
          ? physics::SolidScheme::static_loading()
          : physics::SolidScheme::dynamic(
                physics::GeneralizedAlpha::from_spectral_radius(case_.time.spectral_radius));
  problem_ =
      std::make_unique<physics::SolidProblem>(mesh_, *dmesh_, s.material, s.conditions, scheme);
  solver_ = std::make_unique<physics::SolidSolver>(*problem_, case_.newton);
}

SolidSimulation::~SolidSimulation() = default;

physics::StepReport SolidSimulation::advance() {
  const fem::SolverOptions::Scope options(*options_);
  physics::StepReport r = solver_->step(time(), case_.time.step);
  ++step_;
  return r;
}

std::vector<double> SolidSimulation::gather(Vec v) const {
  fem::OwnedScatter to_all;
  fem::OwnedVec all;
  TF_PETSC(VecScatterCreateToAll(v, to_all.out(), all.out()));
  TF_PETSC(VecScatterBegin(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD));
  TF_PETSC(VecScatterEnd(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD));
  std::vector<double> out(static_cast<size_t>(mesh_.num_nodes()) * block);
  fem::ReadArray a(all);
  const auto& o2g = dmesh_->original_to_global();
  for (Index n = 0; n < mesh_.num_nodes(); ++n)
    for (int c = 0; c < block; ++c)
      out[block * n + c] = a[block * o2g[n] + c];
  return out;
}

void SolidSimulation::set_state(int step, const std::vector<double>& U,
                                const std::vector<double>& D, const std::vector<double>& A) {
  fem::WriteArray u(solver_->solution()), d(solver_->displacement()), a(solver_->acceleration());
  for (Index l = 0; l < dmesh_->num_owned(); ++l) {
    const Index n = dmesh_->original_index(l);
    for (int c = 0; c < block; ++c) {
      u[block * l + c] = U[block * n + c];
      d[block * l + c] = D[block * n + c];
      a[block * l + c] = A[block * n + c];
    }
  }
  step_ = step;
}

void SolidSimulation::write_frame() {
  fem::OwnedVec stress = problem_->dofs().create_global();
  problem_->nodal_stress(solver_->solution(), solver_->displacement(), stress);
  const std::vector<double> U = gather(solver_->solution());
  const std::vector<double> D = gather(solver_->displacement());
  const std::vector<double> S = gather(stress);
  if (fem::mpi_rank(dmesh_->comm()) != 0)
    return;
  io::PointField displacement{"displacement", 3, {}}, velocity{"velocity", 3, {}},
      pressure{"pressure", 1, {}}, von_mises{"von_mises", 1, {}}, jacobian{"J", 1, {}};
  for (Index n = 0; n < mesh_.num_nodes(); ++n) {
    for (int c = 0; c < 3; ++c) {
      displacement.values.push_back(D[block * n + c]);
      velocity.values.push_back(U[block * n + c]);
    }
    pressure.values.push_back(U[block * n + 3]);
    von_mises.values.push_back(S[block * n]);
    jacobian.values.push_back(S[block * n + 1]);
  }
  output_->series->write(step_, time(), {displacement, velocity, pressure, von_mises, jacobian});
}

void SolidSimulation::append_face_rows(std::vector<std::string>& rows) const {
  for (const physics::FaceDisplacement& f : problem_->measure_faces(solver_->displacement()))
    rows.push_back(fmt::format("{},{:.10g},{},{:.10e},{:.10e},{:.10e},{:.10e}", step_, time(),
                               f.face, f.displacement[0], f.displacement[1], f.displacement[2],
                               f.area));
}

RunSummary SolidSimulation::run(const RunOptions& options) {
  const fem::SolverOptions::Scope solver_options(*options_);
  const bool root = fem::mpi_rank(dmesh_->comm()) == 0;
  output_ = std::make_unique<Output>();
  output_->dir = case_.output.directory;
  const std::filesystem::path checkpoint_file = RunFiles{output_->dir}.checkpoint();
  const std::filesystem::path faces_csv = RunFiles{output_->dir}.faces_csv();
  const std::string faces_header = "step,time_s,face,mean_ux_m,mean_uy_m,mean_uz_m,area_m2";
  if (root && options.write_output) {
    std::filesystem::create_directories(output_->dir);
    output_->series = std::make_unique<io::VtuSeries>(mesh_, output_->dir, "solid");
  }

  if (options.restart) {
    // Checkpoint layout: solution (v, p), derivative a, extra u; block 4 each.
    const io::Checkpoint c = io::read_checkpoint(checkpoint_file);
    check_restart(c, run_fingerprint(case_, mesh_), mesh_.num_nodes(), block, case_.time.steps,
                  checkpoint_file);
    if (c.extra.size() != c.solution.size())
      input_error("checkpoint '{}' has {} nodes x {} unknowns, not a solid state of the case's "
                  "mesh ({} x {})",
                  checkpoint_file.string(), c.num_nodes, c.block, mesh_.num_nodes(), block);
    set_state(static_cast<int>(c.step), c.solution, c.extra, c.derivative);
    if (root && options.write_output) {
      output_->series->load_existing(case_.time.step);
      output_->series->truncate_after(time());
      std::ifstream in(faces_csv);
      std::string line;
      std::getline(in, line); // header
      while (std::getline(in, line))
        if (std::stoi(line.substr(0, line.find(','))) <= step_)
          output_->face_rows.push_back(line);
    }
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
    c.time_step = case_.time.step;
    c.num_nodes = mesh_.num_nodes();
    c.block = block;
    c.fingerprint = run_fingerprint(case_, mesh_);
    c.solution = gather(solver_->solution());
    c.derivative = gather(solver_->acceleration());
    c.extra = gather(solver_->displacement());
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
      throw SolverError(fmt::format("{} (step {})", e.what(), step_ + 1), e.collective);
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
      fmt::print("step {:>5}/{}  t = {:.5f} s  Newton {} (|R| {:.2e} -> {:.2e})  KSP {:>4}  "
                 "{:.2f} s/step (assembly {:.2f} s)\n",
                 step_, total, time(), r.newton_iterations, r.residual_initial, r.residual_final,
                 r.linear_iterations, r.assembly_seconds + r.solve_seconds, r.assembly_seconds);
      std::fflush(stdout);
    }
  }
  write_faces_csv();
  summary.wall_seconds = MPI_Wtime() - start;
  return summary;
}

} // namespace tearflow::run
