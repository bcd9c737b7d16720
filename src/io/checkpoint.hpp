#pragma once
// Checkpoints: the complete state needed to continue a run bit for bit: step number, time
// and step, the nodal unknowns and their time derivatives in the input mesh's node order,
// any extra scalar state (0D models), the Newton method reached, and the fingerprint of the
// run that wrote it (named parts of its case: mesh, time step, physics, conditions), so that
// a restart can say what changed. Format 03:
//   "TFCKPT03" | step i64 | time f64 | time_step f64 | nodes i64 | block i32 |
//   parts i32 { name, value: i32 length + bytes } | solution, derivative, extra:
//   i64 count + f64 values | exact_operator i32 | FNV-1a 64 of every byte before it.
// Written through a temporary file, flushed to disk, then renamed over the old one. Reading
// checks the checksum before anything else and every field after; earlier formats (no
// fingerprint, no checksum) are refused, since nothing in them can be checked.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace tearflow::io {

/// Named parts of what a run is (run/run_fingerprint.hpp): {part, description}.
using Fingerprint = std::vector<std::pair<std::string, std::string>>;

struct Checkpoint {
  std::int64_t step = 0;
  double time = 0.0;      ///< step * time_step [s]
  double time_step = 0.0; ///< [s]
  std::int64_t num_nodes = 0;
  std::int32_t block = 0;
  Fingerprint fingerprint;
  std::vector<double> solution;   ///< num_nodes * block
  std::vector<double> derivative; ///< num_nodes * block
  std::vector<double> extra;      ///< scalar states of 0D models
  /// Newton had switched to the exact operator (FSI, physics/fluid_solver.hpp): the restarted
  /// run goes on with it, as the uninterrupted one would.
  bool exact_operator = false;
};

/// InputError naming the file when it cannot be written completely (a full disk, no right
/// to write); the previous checkpoint then stays as it was.
void write_checkpoint(const std::filesystem::path& file, const Checkpoint& c);

/// Throws InputError naming the file when it is missing, truncated, damaged (checksum), of
/// an earlier format, or holds a field out of range (negative step, time not step x
/// time_step, sizes that disagree, a value that is not finite).
Checkpoint read_checkpoint(const std::filesystem::path& file);

} // namespace tearflow::io
