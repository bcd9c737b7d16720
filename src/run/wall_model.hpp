#pragma once
// The wall alone as a run's model (run/model.hpp): SolidProblem stepped by SolidSolver, its
// state the velocity and pressure (solution), the acceleration (derivative) and the
// displacement (a checkpoint's extra); frames with the stress; per face the mean displacement,
// recorded in wall_faces.csv.
#include <memory>
#include <string>
#include <vector>

#include "physics/solid_solver.hpp"
#include "run/model.hpp"

namespace tearflow::run {

class WallModel final : public Model {
public:
  /// InputError unless c.solid is set.
  WallModel(const io::Case& c, const mesh::Mesh& m, const fem::DistributedMesh& dmesh);
  ~WallModel() override;

  physics::SolidProblem& problem() { return *problem_; }
  physics::SolidSolver& solver() { return *solver_; }

  int block() const override { return physics::SolidProblem::block; }
  Vec solution() const override { return solver_->solution(); }
  Vec derivative() const override { return solver_->acceleration(); }
  std::vector<double> extra() const override { return gather(solver_->displacement()); }
  void set_extra(const std::vector<double>& extra, const std::filesystem::path& file) override;

  std::string series_name() const override { return "solid"; }
  std::vector<io::PointField> fields() const override;
  void begin_record() override;
  FaceRecord& record() override;
  std::optional<CycleStats> record_step() override;

private:
  physics::StepReport step_once(double t, double dt) override { return solver_->step(t, dt); }

  std::unique_ptr<physics::SolidProblem> problem_;
  std::unique_ptr<physics::SolidSolver> solver_;
  class Record;
  std::unique_ptr<Record> record_;
};

} // namespace tearflow::run
