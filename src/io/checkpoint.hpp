#pragma once
// Checkpoints: the complete state needed to continue a run bit for bit: step number, time
// and the nodal unknowns and their time derivatives in the input mesh's node order, plus
// any extra scalar state (0D models), and the Newton method reached. Written through a
// temporary file and a rename. Version 01 files (without the method) still read.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tearflow::io {

struct Checkpoint {
  std::int64_t step = 0;
  double time = 0.0;
  std::int64_t num_nodes = 0;
  std::int32_t block = 0;
  std::vector<double> solution;   ///< num_nodes * block
  std::vector<double> derivative; ///< num_nodes * block
  std::vector<double> extra;      ///< scalar states of 0D models
  /// Newton had switched to the exact operator (FSI, physics/fluid_solver.hpp): the restarted
  /// run goes on with it, as the uninterrupted one would.
  bool exact_operator = false;
};

void write_checkpoint(const std::filesystem::path& file, const Checkpoint& c);
/// Throws InputError naming the file when it is missing, truncated or not a checkpoint.
Checkpoint read_checkpoint(const std::filesystem::path& file);

} // namespace tearflow::io
