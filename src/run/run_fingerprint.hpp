#pragma once
// What a checkpoint must agree with to continue a run bit for bit: the named parts of the
// case and mesh that the state depends on. A restart compares them with the checkpoint's and
// refuses a difference, naming each part that changed and how (io/checkpoint.hpp).
#include <filesystem>

#include "io/case.hpp"
#include "io/checkpoint.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::run {

/// The parts: mesh (nodes, tets, regions, a digest of coordinates and connectivity), time
/// step, time scheme, fluid, wall (material, supports, fixed faces), inflow (faces, profile,
/// a digest of the waveform), outlets (faces, types, their numbers and waveforms). Only what
/// the solution depends on: not the output settings, the Newton tolerances or solver options.
io::Fingerprint run_fingerprint(const io::Case& c, const mesh::Mesh& m);

/// InputError naming `file` when the checkpoint does not continue this run: a fingerprint
/// part that differs (each named, with the checkpoint's and the case's description), a
/// different node count or unknowns per node, or a step past `last_step` of the case.
void check_restart(const io::Checkpoint& checkpoint, const io::Fingerprint& now, Index num_nodes,
                   int block, int last_step, const std::filesystem::path& file);

/// InputError naming `file` when the checkpoint cannot start a new run of this case at its
/// time (`run --start-from`): as check_restart, except that the time step and the fluid's
/// stabilization time scale (how the same physics is discretized) may differ, and
/// the checkpoint's time must then be a whole number of the case's steps (the new run's
/// first step number; returned) within 1e-9 of a step.
int check_start(const io::Checkpoint& checkpoint, const io::Fingerprint& now, Index num_nodes,
                int block, double time_step, int last_step, const std::filesystem::path& file);

/// InputError naming `source_case` when that case (whose run wrote the checkpoint a new run
/// starts from, on its own mesh) differs from the case now in anything but the mesh, the
/// time step and the stabilization time scale.
void check_same_but_mesh(const io::Fingerprint& source, const io::Fingerprint& now,
                         const std::filesystem::path& source_case);

} // namespace tearflow::run
