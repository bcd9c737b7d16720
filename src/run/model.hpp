#pragma once
// What a run advances in time, one of three: the flow in rigid walls or with its wall
// (run/flow_model.hpp), or the wall alone (run/wall_model.hpp). The one time loop
// (run/time_loop.hpp) drives any of them through this interface: a step, the state a
// checkpoint keeps, the fields of a frame, the record of the faces, and a start from another
// run's state.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fem/distributed_mesh.hpp"
#include "io/case.hpp"
#include "io/checkpoint.hpp"
#include "io/vtu_series.hpp"
#include "physics/step_report.hpp"
#include "run/run_record.hpp"

namespace tearflow::run {

struct RunOptions;

class Model {
public:
  virtual ~Model() = default;
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;

  int step() const { return step_; }
  double time() const { return step_ * case_.time.step; }
  void set_step(int step) { step_ = step; }
  const io::Case& config() const { return case_; }
  const mesh::Mesh& mesh() const { return mesh_; }
  const fem::DistributedMesh& distributed_mesh() const { return dmesh_; }

  /// One step t -> t + dt of the case (collective). Throws SolverError, the state then left
  /// at t.
  physics::StepReport advance();

  // --- the state, and what a checkpoint keeps ---
  virtual int block() const = 0; ///< unknowns per node of solution() and derivative()
  virtual Vec solution() const = 0;
  virtual Vec derivative() const = 0; ///< its time derivative, as the integrator holds it
  /// The rest of the state, whole on every rank (collective): a checkpoint's `extra`.
  virtual std::vector<double> extra() const = 0;
  /// Sets it back from a checkpoint (`file` names it in messages).
  virtual void set_extra(const std::vector<double>& extra, const std::filesystem::path& file) = 0;
  /// Solver state a restart must repeat (the flows' exact operator, fluid_solver.hpp).
  virtual bool uses_exact_operator() const { return false; }
  virtual void use_exact_operator() {}
  /// Where a checkpoint is written: the next step builds its preconditioner afresh, as a run
  /// restarted there does.
  virtual void rebuild_preconditioner_next() {}
  /// A new run from checkpoint `c` of another run (options.start_from, perhaps of another
  /// mesh: options.start_case): checks it, makes it this mesh's, returns its step.
  virtual int take_state(io::Checkpoint& c, const RunOptions& options) const;

  // --- outputs ---
  virtual std::string series_name() const = 0; ///< of the VTU series ("flow", "solid")
  /// The fields of a frame of the current state (collective; complete on rank 0).
  virtual std::vector<io::PointField> fields() const = 0;
  /// A fresh record of the faces for a run (faces.csv and what it adds up to).
  virtual void begin_record() = 0;
  virtual FaceRecord& record() = 0;
  /// Measures the faces of the current state into the record (collective); returns the
  /// cycle this step completes, if it completes one.
  virtual std::optional<CycleStats> record_step() = 0;
  /// Whether its steps count the Jacobians they assembled (the progress line shows them).
  virtual bool counts_jacobians() const { return false; }
  /// The progress line of a completed cycle (flows).
  virtual void report_cycle(const CycleStats&, bool /*periodic*/) const {}
  /// How the initial state was made, told when a run starts from it.
  virtual std::vector<std::string> start_notes() const { return {}; }

  /// Sets solution and derivative from whole vectors in the input mesh's node order, and the
  /// step.
  void set_state(int step, const std::vector<double>& U, const std::vector<double>& Udot) {
    fem::scatter_nodes(dmesh_, U, solution(), block());
    fem::scatter_nodes(dmesh_, Udot, derivative(), block());
    step_ = step;
  }
  /// A whole node-block vector of this model (gather_nodes).
  std::vector<double> gather(Vec v) const { return fem::gather_nodes(dmesh_, v, block()); }

protected:
  Model(const io::Case& c, const mesh::Mesh& m, const fem::DistributedMesh& dmesh)
      : case_(c), mesh_(m), dmesh_(dmesh) {}
  virtual physics::StepReport step_once(double t, double dt) = 0;

  const io::Case& case_;
  const mesh::Mesh& mesh_;
  const fem::DistributedMesh& dmesh_;

private:
  int step_ = 0;
};

} // namespace tearflow::run
