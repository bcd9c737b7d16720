#pragma once
// The validated description of one simulation: what a case file says, in SI units.
// load_case reads YAML, rejects unknown keys and bad values with the file, line and key;
// docs/case-file.md documents every key.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bc/waveform.hpp"
#include "mesh/mesh.hpp"
#include "mesh/pipe_generator.hpp"

namespace tearflow::io {

struct MeshSpec {
  std::filesystem::path file;         ///< .msh or SimVascular directory (absolute), or empty
  double length_scale = 1.0;          ///< metres per mesh unit (`units: mm` gives 1e-3)
  std::optional<mesh::PipeSpec> pipe; ///< built-in pipe instead of a file
};

struct FluidSpec {
  double density = 1060.0;  ///< [kg/m^3]
  double viscosity = 0.004; ///< dynamic viscosity [Pa s]
};

struct TimeSpec {
  double step = 1e-3;           ///< [s]
  int steps = 100;              ///< number of time steps
  double spectral_radius = 0.5; ///< rho_inf of generalized-alpha, in [0, 1]
};

enum class BcType { NoSlip, Inflow, Pressure, Resistance };
enum class InflowProfile { Parabolic, Plug, Womersley };

struct BoundaryCondition {
  std::string face;
  BcType type = BcType::NoSlip;
  // Inflow: volume flow into the domain [m^3/s] and its spatial profile.
  bc::Waveform flow = bc::Waveform::constant(0.0);
  InflowProfile profile = InflowProfile::Parabolic;
  int womersley_modes = 16;
  // Pressure outlet: normal traction -P n [Pa].
  bc::Waveform pressure = bc::Waveform::constant(0.0);
  // Resistance outlet: P = resistance * Q [Pa s/m^3].
  double resistance = 0.0;
  // Outlets (pressure, resistance): backflow stabilization coefficient.
  double backflow_beta = 0.2;
};

struct NewtonSpec {
  int max_iterations = 10;
  double rtol = 1e-6;  ///< stop when ||R|| <= rtol ||R_0|| ...
  double atol = 1e-10; ///< ... or ||R|| <= atol
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
  std::vector<BoundaryCondition> boundary_conditions;
  NewtonSpec newton;
  std::string petsc_options; ///< passed to PETSc's options database as is
  OutputSpec output;
};

/// Reads and validates a case file. Relative paths are taken from the case file's folder.
Case load_case(const std::filesystem::path& file);

/// Checks the case against its mesh: every BC face exists (InputError listing the known
/// faces otherwise), and no face has two conditions.
void check_case_against_mesh(const Case& c, const mesh::Mesh& m);

} // namespace tearflow::io
