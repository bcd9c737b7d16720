#pragma once
// The flow as a run's model (run/model.hpp): in rigid walls (FlowModel) or with its wall
// (FsiModel, whose state adds the wall's displacement). Both step with the one Newton stepper
// of physics/fluid_solver.hpp; the outlets' 0D states travel in the checkpoint
// (bc/outlet.hpp); a run starts from the outlets' periodic 0D state (run/startup.hpp).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fem/node_transfer.hpp"
#include "physics/fluid_solver.hpp"
#include "physics/fsi_problem.hpp"
#include "run/model.hpp"

namespace tearflow::run {

/// The case's mesh in SI units with outward-oriented faces, checked against the case (the
/// flow's region of it in rigid walls).
mesh::Mesh load_mesh(const io::Case& c);
/// The case's boundary conditions resolved against the mesh.
bc::FluidConditions make_conditions(const io::Case& c, const mesh::Mesh& m);
physics::FluidProperties fluid_properties(const io::Case& c);

/// physics::NewtonStepper of the rigid or the FSI problem, behind one interface.
class FlowStepper {
public:
  virtual ~FlowStepper() = default;
  virtual Vec solution() const = 0;
  virtual Vec acceleration() const = 0;
  virtual physics::StepReport step(double t, double dt) = 0;
  virtual bool uses_exact_operator() const = 0;
  virtual void use_exact_operator() = 0;
  virtual void rebuild_preconditioner_next() = 0;
};
std::unique_ptr<FlowStepper> make_stepper(physics::FluidProblem& p, const physics::NewtonSpec& n);
std::unique_ptr<FlowStepper> make_stepper(physics::FsiProblem& p, const physics::NewtonSpec& n);

class FlowModel : public Model {
public:
  /// The flow in rigid walls, started as time.start says.
  FlowModel(const io::Case& c, const mesh::Mesh& m, const fem::DistributedMesh& dmesh);
  ~FlowModel() override;

  /// The flow problem: the rigid-wall one, or the fluid of the FSI problem.
  physics::FluidProblem& fluid() const { return *fluid_; }
  /// The face measures of the current state (collective).
  StepSample sample() const;
  /// The current state with the fluid's pressure at the state's time t_{n+1} (collective).
  /// Generalized-alpha poses the step's equations at t_n + alpha_f dt, where the pressure
  /// unknown is the multiplier of the stage's continuity: taken as it is beside the velocity
  /// at t_{n+1}, it lagged by (1 - alpha_f) dt (a third of a step at rho_inf 0.5). It is
  /// extrapolated linearly from the last two stages; frames and faces.csv show it, the
  /// unknown itself goes to the frames as `stage_pressure` (the conservative flux reads it).
  fem::OwnedVec state_at_step_time() const;

  int block() const override { return physics::FluidProblem::block; }
  Vec solution() const override { return stepper_->solution(); }
  Vec derivative() const override { return stepper_->acceleration(); }
  /// Per outlet its law's record and Q at t_n (then, with a wall, its displacement).
  std::vector<double> extra() const override;
  void set_extra(const std::vector<double>& extra, const std::filesystem::path& file) override;
  bool uses_exact_operator() const override { return stepper_->uses_exact_operator(); }
  void use_exact_operator() override { stepper_->use_exact_operator(); }
  void rebuild_preconditioner_next() override { stepper_->rebuild_preconditioner_next(); }
  int take_state(io::Checkpoint& c, const RunOptions& options) const override;

  std::string series_name() const override { return "flow"; }
  std::vector<io::PointField> fields() const override;
  void begin_record() override;
  FaceRecord& record() override { return *record_; }
  std::optional<CycleStats> record_step() override { return record_->add(sample()); }
  bool counts_jacobians() const override { return true; }
  void report_cycle(const CycleStats& c, bool periodic) const override;
  std::vector<std::string> start_notes() const override { return start_notes_; }

protected:
  struct Unstarted {};
  /// Nothing built yet: FsiModel builds its problem and stepper, then starts.
  FlowModel(const io::Case& c, const mesh::Mesh& m, const fem::DistributedMesh& dmesh, Unstarted)
      : Model(c, m, dmesh) {}
  physics::StepReport step_once(double t, double dt) override { return stepper_->step(t, dt); }
  /// The outlets' states and the pressure field from the outlets' periodic 0D state at t = 0
  /// (time.start); returns the pressure it set, or nothing when there is no 0D model.
  std::optional<double> start_from_0d();
  /// The region each unknown of a node interpolates in when a state moves to this mesh.
  virtual std::vector<std::string> unknown_regions() const { return {"", "", "", ""}; }
  /// The wall's part of the state, its displacement of every node, whole on every rank
  /// (collective; none in rigid walls), its size, and setting it back.
  virtual std::vector<double> wall_state() const { return {}; }
  virtual size_t wall_state_size() const { return 0; }
  virtual void set_wall_state(std::vector<double>) {}

  physics::FluidProblem* fluid_ = nullptr;
  std::unique_ptr<FlowStepper> stepper_;
  std::vector<std::string> start_notes_;

private:
  size_t outlet_record_size() const;               ///< the outlets' part of extra()
  std::unique_ptr<physics::FluidProblem> problem_; ///< rigid walls
  std::unique_ptr<RunRecord> record_;
};

class FsiModel final : public FlowModel {
public:
  /// The flow with its wall (a mesh with regions `fluid` and `wall`), started as time.start
  /// says, the wall loaded with the start's pressure.
  FsiModel(const io::Case& c, const mesh::Mesh& m, const fem::DistributedMesh& dmesh);
  ~FsiModel() override;

  int block() const override { return physics::FsiProblem::block; }

private:
  std::vector<std::string> unknown_regions() const override;
  std::vector<double> wall_state() const override;
  size_t wall_state_size() const override;
  void set_wall_state(std::vector<double> displacement) override;
  /// The wall in quasi-static equilibrium with the fluid pressure p0 (the start).
  void load_wall(double p0);

  std::unique_ptr<physics::FsiProblem> fsi_;
};

} // namespace tearflow::run
