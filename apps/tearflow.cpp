// tearflow: the command-line program.
//   tearflow run [CASE.yaml] [--restart | --start-from CHECKPOINT [--start-case CASE]] [-o DIR]
//   [--steps N] [--targets T.yaml] [-- PETSc] tearflow verify NAME [--convergence] | --list
//   tearflow geometry tbad|import|report ...   (docs/geometry.md) tearflow tune CASE.yaml --targets
//   TARGETS.yaml [-o TUNED.yaml]   (docs/tuning.md) tearflow analyze RUN_DIR [--landmarks FILE]
//   [--cycle N |
//   --frames all]   (docs/analysis.md) tearflow report RUN_DIR [RUN_DIR...] [-o FILE] [--png]
//   (docs/analysis.md) tearflow study STUDY.yaml [--check] (docs/study.md) tearflow mri
//   synthesize|flow|compare ...                                 (docs/mri.md)
//   tearflow pictures RUN_DIR [--time T] [--seed L] [--animate]  (docs/analysis.md)
// PETSc options go after `--` (or in the case file's petsc_options); those on the command
// line win over the case file's.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <petscsys.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "analysis/analyze_command.hpp"
#include "core/error.hpp"
#include "fem/petsc.hpp"
#include "geometry/geometry_command.hpp"
#include "io/case.hpp"
#include "mri/mri_command.hpp"
#include "report/pictures_command.hpp"
#include "report/report_command.hpp"
#include "rom/rom_command.hpp"
#include "run/default_case.hpp"
#include "run/run_lock.hpp"
#include "run/simulation.hpp"
#include "run/solid_simulation.hpp"
#include "study/study_command.hpp"
#include "tuning/corrected_run.hpp"
#include "tuning/targets.hpp"
#include "tuning/tune_command.hpp"
#include "verify/verification.hpp"

using namespace tearflow;

namespace {

/// "create directories" from std::filesystem's "filesystem error: cannot create
/// directories: <reason> [<path>]" (its what() names the operation).
std::string filesystem_action(const std::string& what) {
  const std::string prefix = "filesystem error: cannot ";
  const size_t begin = what.find(prefix), end = what.find(':', begin + prefix.size());
  if (begin == std::string::npos || end == std::string::npos)
    return "write";
  return what.substr(begin + prefix.size(), end - begin - prefix.size());
}

/// The case, read by every rank from the same file: a bad case is the same error on every
/// rank, so it is reported once and ends all ranks without MPI_Abort (issue 28, item 7).
io::Case load_case_everywhere(const std::string& file) {
  try {
    return io::load_case(file);
  } catch (const InputError& e) {
    throw InputError(e.what(), true);
  }
}

/// `tearflow run`'s arguments.
struct RunArgs {
  std::string case_file, output, targets_file, start_from, start_case;
  bool restart = false, quiet = false;
  int steps = 0;
  std::string command_line; ///< as typed (PETSc's options aside), for the folder's lock
};

int run_command(const RunArgs& args, const std::string& cli_petsc) {
  const auto& [case_file, output, targets_file, start_from, start_case, restart, quiet, steps,
               command_line] = args;
  io::Case c = case_file.empty() ? run::default_case() : load_case_everywhere(case_file);
  if (steps > 0)
    c.time.steps = steps;
  if (!output.empty())
    c.output.directory = std::filesystem::absolute(output);
  // The run's PETSc options (fem/solver_options.hpp): the case's, then the command line's,
  // which so win.
  c.petsc_options += cli_petsc;
  const bool root = fem::mpi_rank() == 0;
  if (root && !quiet)
    fmt::print("tearflow run '{}': {} steps of {} s, output in '{}'\n", c.name, c.time.steps,
               c.time.step, c.output.directory.string());
  if (!start_case.empty() && start_from.empty())
    collective_input_error(
        "--start-case names the case of --start-from's run: give --start-from too");
  if (!start_from.empty()) {
    if (restart || !targets_file.empty())
      collective_input_error("--start-from starts a new run: not with --restart or --targets");
    if (c.solid && c.boundary_conditions.empty())
      collective_input_error("--start-from is for flow and FSI cases, not a solid-only case");
    // The new run's files would replace the run the state comes from.
    if (std::filesystem::weakly_canonical(std::filesystem::absolute(start_from)).parent_path() ==
        std::filesystem::weakly_canonical(c.output.directory))
      collective_input_error(
          "--start-from '{}' lies in the output folder '{}': the new run would replace "
          "that run's files; give another folder with -o",
          start_from, c.output.directory.string());
  }
  // One run per output folder, held until this command returns (run/run_lock.hpp): before
  // anything is written there (the built-in case writes its model into it).
  const std::unique_ptr<io::OutputLock> lock = run::hold_run_folder(
      c.output.directory, fmt::format("{} (case '{}')", command_line, c.name), PETSC_COMM_WORLD);
  if (!targets_file.empty()) { // outlets corrected at cycle ends (tuning/corrected_run.hpp)
    if (case_file.empty() || (c.solid && c.boundary_conditions.empty()))
      collective_input_error("--targets needs a flow case with RCR outlets (docs/tuning.md)");
    const tuning::CorrectedRun r =
        tuning::run_corrected(c, case_file, tuning::load_targets(targets_file), targets_file,
                              {restart, {}, {}, !quiet, true, {}});
    if (root && !quiet)
      fmt::print("done: {} steps in {:.1f} s, targets {} by the last cycle; results and the "
                 "tuned case in '{}'\n",
                 r.summary.steps, r.summary.wall_seconds, r.met ? "met" : "NOT met",
                 c.output.directory.string());
    return 0;
  }
  auto execute = [&](auto& sim) {
    if (root && !quiet)
      fmt::print("mesh: {} nodes, {} tets on {} rank(s)\n", sim.mesh().num_nodes(),
                 sim.mesh().num_tets(), fem::mpi_size());
    run::RunOptions options{restart, start_from, start_case, !quiet, true, {}};
    const run::RunSummary s = sim.run(options);
    if (root && !quiet)
      fmt::print("done: {} steps in {:.1f} s; results in '{}'\n", s.steps, s.wall_seconds,
                 sim.config().output.directory.string());
  };
  if (c.solid && c.boundary_conditions.empty()) { // a solid-only case
    run::SolidSimulation sim(std::move(c));
    execute(sim);
  } else {
    run::Simulation sim(std::move(c));
    execute(sim);
  }
  return 0;
}

/// Prints the error once (a collective one on rank 0 only) and returns the exit code: 2 bad
/// input or an unwritable file, 3 a solver failure, 1 anything else. `collective`: every
/// rank has the same error (none is left waiting in a collective call).
int report_error(std::exception_ptr error, bool& collective) {
  collective = false;
  try {
    std::rethrow_exception(error);
  } catch (const InputError& e) {
    if (!e.collective || fem::mpi_rank() == 0)
      std::fprintf(stderr, "error: %s\n", e.what());
    collective = e.collective;
    return 2;
  } catch (const SolverError& e) {
    if (!e.collective || fem::mpi_rank() == 0)
      std::fprintf(stderr, "error: %s\n", e.what());
    collective = e.collective;
    return 3;
  } catch (const std::filesystem::filesystem_error& e) {
    // A folder that cannot be made or a file that cannot be written (read-only, full):
    // the path and the system's reason, as for the writes that check themselves.
    std::fprintf(stderr, "error: cannot %s '%s': %s\n", filesystem_action(e.what()).c_str(),
                 e.path1().string().c_str(), e.code().message().c_str());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory: the input asks for more memory than this process "
                         "could get (a mesh, element size, image size or mode count too large "
                         "for this machine?)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}

/// A command that runs on one process: rank 0 runs it, and its exit code, an error's
/// included, goes to every rank, so all end alike without MPI_Abort (issue 28, item 7).
template <typename Command> int on_one_rank(const char* name, Command&& command) {
  int code = 0;
  if (fem::mpi_rank() == 0) {
    if (fem::mpi_size() > 1)
      std::fprintf(stderr, "note: `tearflow %s` runs on one process; the other %d rank(s) wait\n",
                   name, fem::mpi_size() - 1);
    try {
      code = command();
    } catch (...) {
      bool collective = false;
      code = report_error(std::current_exception(), collective);
    }
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  return code;
}

/// While alive, what the process writes to stdout goes to stderr: the progress lines that
/// a verification case's runs print (a run's own output is stdout), so that stdout carries
/// the case's JSON alone.
class StdoutToStderr {
public:
  StdoutToStderr() : saved_(dup(STDOUT_FILENO)) {
    std::fflush(stdout);
    dup2(STDERR_FILENO, STDOUT_FILENO);
  }
  ~StdoutToStderr() {
    std::fflush(stdout);
    dup2(saved_, STDOUT_FILENO);
    close(saved_);
  }
  StdoutToStderr(const StdoutToStderr&) = delete;
  StdoutToStderr& operator=(const StdoutToStderr&) = delete;

private:
  int saved_;
};

int verify_command(const std::string& name, bool list, const verify::VerifyOptions& options) {
  const auto& cases = verify::verification_cases();
  const bool root = fem::mpi_rank() == 0;
  if (list || name.empty()) {
    if (root)
      for (const auto& [n, c] : cases)
        fmt::print("{:<12} {}\n", n, c.description);
    return 0;
  }
  const auto it = cases.find(name);
  if (it == cases.end()) {
    std::string known;
    for (const auto& [n, c] : cases)
      known += " " + n;
    input_error("no verification case '{}'; known:{}", name, known);
  }
  const verify::VerificationResult r = [&] {
    const StdoutToStderr redirect;
    return it->second.run(options);
  }();
  if (root)
    fmt::print("{}\n", r.to_json().dump(2));
  // Rank 0's verdict for every rank, so that a failed check ends the run on all of them
  // alike (main then needs no MPI_Abort).
  int passed = r.passed() ? 1 : 0;
  MPI_Bcast(&passed, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  return passed ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
  // Log lines go to stderr: stdout carries results (verify prints JSON there).
  spdlog::set_default_logger(spdlog::stderr_color_mt("tearflow"));
  // Split at `--`: ours before, PETSc's after.
  std::vector<char*> ours, petsc{argv[0]};
  std::string cli_petsc;
  bool after = false;
  for (int i = 0; i < argc; ++i) {
    if (!after && std::string(argv[i]) == "--") {
      after = true;
      continue;
    }
    if (after) {
      cli_petsc += std::string(" ") + argv[i];
    } else {
      ours.push_back(argv[i]);
    }
  }
  int petsc_argc = 1;
  char** petsc_argv = petsc.data();
  fem::PetscSession session(&petsc_argc, &petsc_argv);

  CLI::App app{"tearflow: blood flow and pressure in type B aortic dissection"};
  app.require_subcommand(1);
  RunArgs run_args;
  std::string verify_name;
  bool list = false;
  verify::VerifyOptions verify_options;
  auto* run = app.add_subcommand("run", "run a simulation case (built-in pulsatile pipe if none)");
  run->add_option("case", run_args.case_file, "case file (YAML)");
  run->add_flag("--restart", run_args.restart, "continue from the output directory's checkpoint");
  run->add_option("--start-from", run_args.start_from,
                  "start a new run from this checkpoint's state and time (the same case; its "
                  "time step may differ)");
  run->add_option("--start-case", run_args.start_case,
                  "the case of --start-from's run, when its mesh is another one: the state is "
                  "interpolated to this case's mesh");
  run->add_option("-o,--output", run_args.output, "output directory (overrides the case file)");
  run->add_flag("-q,--quiet", run_args.quiet, "no progress lines");
  run->add_option("--steps", run_args.steps, "stop at this step (overrides time.steps and cycles)")
      ->check(CLI::Range(1, 1000000000)); // not PositiveNumber: its message prints DBL_MAX
  run->add_option("--targets", run_args.targets_file,
                  "correct the RCR outlets at every cycle's end until a periodic cycle meets "
                  "these targets (docs/tuning.md)");
  auto* verify = app.add_subcommand("verify", "run a built-in verification case, print JSON");
  verify->add_option("name", verify_name, "case name (see --list)");
  verify->add_flag("--list", list, "list the verification cases");
  verify->add_flag("--convergence", verify_options.convergence, "add the mesh-refinement study");
  verify
      ->add_option("--coarsen", verify_options.coarsening,
                   "mesh size factor (> 1 coarser; CI's reduced form)")
      ->check(CLI::Range(0.25, 8.0));
  verify->add_flag("--reduced", verify_options.reduced,
                   "CI's short form where coarsening cannot shorten a case (pulse)");
  verify->add_flag("--progress", verify_options.progress, "progress lines on stderr");
  verify->add_option("-o,--output", verify_options.output,
                     "directory for the case's time series (CSV)");
  const geometry::GeometryCommand geometry_command(app);
  const tuning::TuneCommand tune_command(app);
  const analysis::AnalyzeCommand analyze_command(app);
  const report::ReportCommand report_command(app);
  const report::PicturesCommand pictures_command(app);
  const study::StudyCommand study_command(app);
  const mri::MriCommand mri_command(app);
  const rom::RomCommand rom_command(app);

  run_args.command_line = std::filesystem::path(ours.front()).filename().string();
  for (std::size_t i = 1; i < ours.size(); ++i)
    run_args.command_line += std::string(" ") + ours[i];
  int code = 0;
  bool all_ranks_stopped = false; // every rank caught the same error: none is left waiting
  try {
    app.parse(static_cast<int>(ours.size()), ours.data());
    if (*run)
      code = run_command(run_args, cli_petsc);
    if (*verify) {
      code = verify_command(verify_name, list, verify_options);
      all_ranks_stopped = true; // the same code on every rank
    }
    // Serial commands: one rank writes.
    const bool serial = geometry_command.selected() || analyze_command.selected() ||
                        report_command.selected() || pictures_command.selected() ||
                        mri_command.selected() || rom_command.selected();
    if (geometry_command.selected())
      code = on_one_rank("geometry", [&] { return geometry_command.run(); });
    if (tune_command.selected())
      code = tune_command.run(cli_petsc);
    if (analyze_command.selected())
      code = on_one_rank("analyze", [&] { return analyze_command.run(); });
    if (report_command.selected())
      code = on_one_rank("report", [&] { return report_command.run(); });
    if (pictures_command.selected())
      code = on_one_rank("pictures", [&] { return pictures_command.run(); });
    if (study_command.selected())
      code = study_command.run();
    if (mri_command.selected())
      code = on_one_rank("mri", [&] { return mri_command.run(); });
    if (rom_command.selected())
      code = on_one_rank("rom", [&] { return rom_command.run(); });
    all_ranks_stopped = all_ranks_stopped || serial;
  } catch (const CLI::ParseError& e) {
    // Every rank parsed the same arguments: the same error (or --help) on each, said once.
    std::ostringstream quiet;
    code = fem::mpi_rank() == 0 ? app.exit(e) : app.exit(e, quiet, quiet);
    all_ranks_stopped = true;
  } catch (...) {
    code = report_error(std::current_exception(), all_ranks_stopped);
  }
  // An error seen by one rank only would leave the others waiting in a collective call.
  if (code != 0 && !all_ranks_stopped && fem::mpi_size() > 1)
    MPI_Abort(PETSC_COMM_WORLD, code);
  return code;
}
