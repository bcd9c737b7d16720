#pragma once
// The validated description of one simulation: what a case file says, in SI units.
// load_case reads YAML, rejects unknown keys and bad values with the file, line and key;
// docs/case-file.md documents every key.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bc/boundary_condition.hpp"
#include "bc/waveform.hpp"
#include "io/case_solid.hpp"
#include "mesh/mesh.hpp"
#include "mesh/pipe_generator.hpp"
#include "physics/navier_stokes_kernel.hpp"
#include "physics/newton_spec.hpp"

namespace tearflow::io {

struct MeshSpec {
  std::filesystem::path file; ///< .msh or SimVascular directory (absolute), or empty
  /// The wall's mesh when it is a separate file (FSI; interface nodes coincide with file's)
  std::filesystem::path wall_file;
  double length_scale = 1.0;          ///< metres per mesh unit (`units: mm` gives 1e-3)
  std::optional<mesh::PipeSpec> pipe; ///< built-in pipe instead of a file
  /// The volume region the flow is solved in (a multi-region mesh's `fluid` if empty).
  std::string region;
  /// Built-in geometry (the default case, verification cases; not from case files): called
  /// with the case, wins over file and pipe.
  std::function<mesh::Mesh(const struct Case&)> generator;
};

/// The fluid and how its stabilization is formed (physics/navier_stokes_kernel.hpp).
using FluidSpec = physics::FluidProperties;

struct TimeSpec {
  double step = 1e-3;           ///< [s]
  int steps = 100;              ///< number of time steps (the most, with a periodicity stop)
  double spectral_radius = 0.5; ///< rho_inf of generalized-alpha, in [0, 1]
  /// Cardiac cycle [s]: the waveforms' period unless given; 0 when everything is constant.
  double period = 0.0;
  int steps_per_cycle = 0; ///< period / step when the period is a multiple of the step
  /// Stop once the cycle-to-cycle change is below this (0: run all steps).
  double periodicity_tolerance = 0.0;
  /// What that change measures (run/cycle_summary.hpp): every outlet's flow and pressure
  /// waveform sample by sample, or the cycle's numbers (inlet pressures, outlet splits).
  enum class Periodicity {
    waveforms,
    pressures_and_splits
  } periodicity_measure = Periodicity::waveforms;
  /// Start the RCR outlets (and the pressure field) from the periodic state of the 0D model
  /// of the outlets instead of their initial_distal_pressure and rest.
  bool start_from_0d = true;
};

struct OutputSpec {
  std::filesystem::path directory; ///< absolute; default `results/<name>` under the cwd
  int every = 10;                  ///< save a VTU every n steps (0: only the last)
  int checkpoint_every = 0;        ///< 0: no checkpoints
};

struct Case {
  std::string name = "case";
  std::filesystem::path file; ///< the case file, empty for built-in cases
  MeshSpec mesh;
  FluidSpec fluid;
  TimeSpec time;
  std::vector<bc::BoundaryCondition> boundary_conditions; ///< bc/boundary_condition.hpp
  std::optional<SolidSpec> solid; ///< the wall; a solid-only case has no fluid conditions
  physics::NewtonSpec newton;
  std::string petsc_options; ///< passed to PETSc's options database as is
  OutputSpec output;
};

/// Reads and validates a case file. Relative paths are taken from the case file's folder.
Case load_case(const std::filesystem::path& file);

/// Checks the case against its mesh: every BC face exists (InputError listing the known
/// faces otherwise), and no face has two conditions.
void check_case_against_mesh(const Case& c, const mesh::Mesh& m);

/// A case with both flow conditions and a solid: fluid-structure interaction on a mesh with
/// a `fluid` and a `wall` region.
inline bool is_fsi(const Case& c) {
  return c.solid && !c.boundary_conditions.empty();
}

} // namespace tearflow::io
