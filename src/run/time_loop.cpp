#include "run/time_loop.hpp"

#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "fem/alike_on_every_rank.hpp"
#include "fem/petsc.hpp"
#include "io/durable_file.hpp"
#include "io/vtu_series.hpp"
#include "run/model.hpp"
#include "run/run_fingerprint.hpp"

namespace tearflow::run {

RunSummary run_loop(Model& model, const RunOptions& options) {
  const io::Case& c = model.config();
  const mesh::Mesh& mesh = model.mesh();
  const MPI_Comm comm = model.distributed_mesh().comm();
  const bool root = fem::mpi_rank(comm) == 0;
  const bool write = options.write_output;
  const RunFiles files{c.output.directory};
  const std::filesystem::path checkpoint_file = files.checkpoint();
  std::unique_ptr<io::VtuSeries> series;
  if (root && write) {
    std::filesystem::create_directories(files.dir);
    series = std::make_unique<io::VtuSeries>(mesh, files.dir, model.series_name());
  }
  model.begin_record();
  FaceRecord& record = model.record();
  const std::filesystem::path record_file = record.file(files);

  auto write_frame = [&] {
    const std::vector<io::PointField> fields = model.fields(); // collective
    if (root)
      series->write(model.step(), model.time(), fields);
  };
  auto write_record = [&] {
    if (!root || !write)
      return;
    io::write_file_atomically(record_file, record.csv());
    if (const std::optional<nlohmann::json> cycles = record.cycles_record())
      io::write_file_atomically(files.cycles_json(), cycles->dump(2) + "\n");
  };
  auto set_state = [&](int step, const io::Checkpoint& from, const std::filesystem::path& file) {
    model.set_state(step, from.solution, from.derivative);
    model.set_extra(from.extra, file);
  };

  if (options.restart) {
    // Every rank reads the checkpoint; a missing or damaged one stops all with one message.
    const io::Checkpoint cp = fem::alike_on_every_rank(comm, [&] {
      io::Checkpoint read = io::read_checkpoint(checkpoint_file);
      check_restart(read, run_fingerprint(c, mesh), mesh.num_nodes(), model.block(), c.time.steps,
                    checkpoint_file);
      return read;
    });
    set_state(static_cast<int>(cp.step), cp, checkpoint_file);
    if (cp.exact_operator) // the method the run had switched to (fluid_solver.cpp)
      model.use_exact_operator();
    if (write) {
      record.load_csv(record_file, model.step()); // every rank: all must agree on periodicity
      if (root) {
        io::write_file_atomically(record_file, record.csv()); // without rows after the checkpoint
        series->load_existing(c.time.step);
        series->truncate_after(model.time());
      }
    }
    if (root && options.progress)
      fmt::print("restarting from step {} (t = {:.6g} s) of '{}'{}\n", model.step(), model.time(),
                 checkpoint_file.string(), cp.exact_operator ? ", with the exact operator" : "");
  } else {
    if (!options.start_from.empty()) {
      io::Checkpoint cp =
          fem::alike_on_every_rank(comm, [&] { return io::read_checkpoint(options.start_from); });
      const int first = model.take_state(cp, options);
      set_state(first, cp, options.start_from);
      // Not the exact operator the run may have switched to: that was its step's need; at
      // another step Newton falls back to it again if it must (fluid_solver.cpp).
      if (root && options.progress)
        spdlog::info("start from the state at t = {:.6g} s of '{}' (its step {} s, now {} s)",
                     model.time(), options.start_from.string(), cp.time_step, c.time.step);
    } else if (root && options.progress) {
      for (const std::string& note : model.start_notes())
        spdlog::info("{}", note);
    }
    if (write)
      write_frame();
    model.record_step();
    if (root && write) // then a row per step as the run goes
      io::write_file_atomically(record_file, record.csv());
  }

  auto write_checkpoint = [&] {
    io::Checkpoint cp;
    cp.step = model.step();
    cp.time = model.time();
    cp.time_step = c.time.step;
    cp.num_nodes = mesh.num_nodes();
    cp.block = model.block();
    cp.fingerprint = run_fingerprint(c, mesh); // the outlets as they run now
    cp.solution = model.gather(model.solution());
    cp.derivative = model.gather(model.derivative());
    cp.extra = model.extra();
    cp.exact_operator = model.uses_exact_operator();
    if (root)
      io::write_checkpoint(checkpoint_file, cp);
    // A restart from here builds its preconditioner afresh: so does the run going on.
    model.rebuild_preconditioner_next();
  };

  RunSummary summary;
  const double start = MPI_Wtime();
  const int total = c.time.steps;
  bool periodic = false;
  while (model.step() < total && !periodic) {
    physics::StepReport r;
    try {
      r = model.advance();
    } catch (const SolverError& e) {
      write_record();
      throw SolverError(fmt::format("{} (step {}). {}", e.what(), model.step() + 1,
                                    c.output.checkpoint_every > 0 && write &&
                                            std::filesystem::exists(checkpoint_file)
                                        ? "The last good checkpoint is kept in '" +
                                              checkpoint_file.string() + "'."
                                        : "No checkpoint was written."),
                        e.collective);
    }
    summary.reports.push_back(r);
    ++summary.steps;
    const std::optional<run::CycleStats> cycle = model.record_step();
    if (root && write) // a killed run keeps every step it finished
      io::append_to_file(record_file, record.last_rows());
    if (cycle) {
      periodic = c.time.periodicity_tolerance > 0.0 && cycle->change &&
                 *cycle->change < c.time.periodicity_tolerance;
      if (root && options.progress)
        model.report_cycle(*cycle, periodic);
      if (options.on_cycle)
        periodic = options.on_cycle(*cycle, periodic); // "periodic" now: the run stops
    }
    if (write) {
      const int step = model.step();
      const bool last = step == total || periodic;
      if ((c.output.every > 0 && step % c.output.every == 0) || last)
        write_frame();
      if (c.output.checkpoint_every > 0 && (step % c.output.checkpoint_every == 0 || last)) {
        write_record();
        write_checkpoint();
      }
    }
    if (root && options.progress) {
      const double elapsed = MPI_Wtime() - start;
      const double eta = elapsed / summary.steps * (total - model.step());
      // The solve that counted, and apart what a failed attempt spent before it.
      const std::string newton =
          r.retried_iterations > 0
              ? fmt::format("{} (+{} retried)", r.newton_iterations - r.retried_iterations,
                            r.retried_iterations)
              : fmt::format("{}", r.newton_iterations);
      const std::string jacobians =
          model.counts_jacobians() ? fmt::format(", Jacobians {}", r.jacobians) : std::string();
      fmt::print("step {:>5}/{}  t = {:.5f} s  Newton {} (|R| {:.2e} -> {:.2e}{})  "
                 "KSP {:>4}  {:.2f} s/step (assembly {:.2f} s)  ETA {:.0f} s\n",
                 model.step(), total, model.time(), newton, r.residual_initial, r.residual_final,
                 jacobians, r.linear_iterations, r.assembly_seconds + r.solve_seconds,
                 r.assembly_seconds, eta);
      std::fflush(stdout);
    }
  }
  write_record();
  if (c.time.periodicity_tolerance > 0.0 && !periodic && root)
    spdlog::warn("not periodic within {} after {} cycle(s) ({}); raise "
                 "time.periodicity.max_cycles to continue with --restart",
                 c.time.periodicity_tolerance, record.cycles().size(),
                 record.cycles().empty() || !record.cycles().back().change
                     ? std::string("no two complete cycles to compare")
                     : fmt::format("last change {:.3g}", *record.cycles().back().change));
  summary.wall_seconds = MPI_Wtime() - start;
  summary.periodic = periodic;
  summary.cycles = record.cycles();
  return summary;
}

} // namespace tearflow::run
