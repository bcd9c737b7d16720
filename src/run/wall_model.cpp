#include "run/wall_model.hpp"

#include <fstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "fem/petsc.hpp"
#include "io/case_solid.hpp"

namespace tearflow::run {

namespace {
std::string source_of(const io::Case& c) {
  return c.file.empty() ? fmt::format("case '{}'", c.name) : c.file.string();
}
} // namespace

/// Per step and named face of the wall, its mean displacement and reference area.
class WallModel::Record final : public FaceRecord {
public:
  static constexpr const char* header = "step,time_s,face,mean_ux_m,mean_uy_m,mean_uz_m,area_m2";

  std::filesystem::path file(const RunFiles& run) const override { return run.wall_faces_csv(); }
  std::string csv() const override {
    std::string text = std::string(header) + "\n";
    for (const std::string& r : rows_)
      text += r + "\n";
    return text;
  }
  std::string last_rows() const override {
    std::string text;
    for (size_t i = rows_.size() - last_; i < rows_.size(); ++i)
      text += rows_[i] + "\n";
    return text;
  }
  void load_csv(const std::filesystem::path& file, int last_step) override {
    rows_.clear();
    last_ = 0;
    std::ifstream in(file);
    std::string line;
    std::getline(in, line); // header
    for (int number = 2; std::getline(in, line); ++number) {
      // Rows are appended as steps end: a last line without its newline was cut short by a
      // kill or a full disk (after the checkpoint's step, whose rewrite ended in a newline).
      if (line.empty() || in.eof())
        continue;
      int step = 0;
      try {
        step = std::stoi(line.substr(0, line.find(',')));
      } catch (const std::exception&) {
        input_error("{}:{}: expected a row '{}', got '{}'", file.string(), number, header, line);
      }
      if (step <= last_step)
        rows_.push_back(line);
    }
  }
  const std::vector<CycleStats>& cycles() const override { return no_cycles_; }

  void add(int step, double time, const std::vector<physics::FaceDisplacement>& faces) {
    for (const physics::FaceDisplacement& f : faces)
      rows_.push_back(fmt::format("{},{:.10g},{},{:.10e},{:.10e},{:.10e},{:.10e}", step, time,
                                  f.face, f.displacement[0], f.displacement[1], f.displacement[2],
                                  f.area));
    last_ = faces.size();
  }

private:
  std::vector<std::string> rows_;
  size_t last_ = 0; ///< rows of the last step added
  std::vector<CycleStats> no_cycles_;
};

WallModel::WallModel(const io::Case& c, const mesh::Mesh& m, const fem::DistributedMesh& dmesh)
    : Model(c, m, dmesh) {
  if (!c.solid)
    input_error("{}: a solid simulation needs a `solid:` section", source_of(c));
  const io::SolidSpec& s = *c.solid;
  io::check_solid_against_mesh(s, m, source_of(c));
  const physics::SolidScheme scheme =
      s.quasi_static ? physics::SolidScheme::static_loading()
                     : physics::SolidScheme::dynamic(
                           physics::GeneralizedAlpha::from_spectral_radius(c.time.spectral_radius));
  problem_ = std::make_unique<physics::SolidProblem>(m, dmesh, s.material, s.conditions, scheme);
  solver_ = std::make_unique<physics::SolidSolver>(*problem_, c.newton);
}

WallModel::~WallModel() = default;

void WallModel::set_extra(const std::vector<double>& extra, const std::filesystem::path& file) {
  const size_t size = static_cast<size_t>(mesh_.num_nodes()) * block();
  if (extra.size() != size)
    input_error("checkpoint '{}' holds {} values beside the solution, not the displacement of "
                "the case's mesh ({} nodes x {} unknowns)",
                file.string(), extra.size(), mesh_.num_nodes(), block());
  fem::scatter_nodes(dmesh_, extra, solver_->displacement(), block());
}

std::vector<io::PointField> WallModel::fields() const {
  fem::OwnedVec stress = problem_->dofs().create_global();
  problem_->nodal_stress(solver_->solution(), solver_->displacement(), stress);
  const std::vector<double> U = gather(solver_->solution());
  const std::vector<double> D = gather(solver_->displacement());
  const std::vector<double> S = gather(stress);
  if (fem::mpi_rank(dmesh_.comm()) != 0)
    return {};
  const int bs = block();
  io::PointField displacement{"displacement", 3, {}}, velocity{"velocity", 3, {}},
      pressure{"pressure", 1, {}}, von_mises{"von_mises", 1, {}}, jacobian{"J", 1, {}};
  for (Index n = 0; n < mesh_.num_nodes(); ++n) {
    for (int c = 0; c < 3; ++c) {
      displacement.values.push_back(D[bs * n + c]);
      velocity.values.push_back(U[bs * n + c]);
    }
    pressure.values.push_back(U[bs * n + 3]);
    von_mises.values.push_back(S[bs * n]);
    jacobian.values.push_back(S[bs * n + 1]);
  }
  return {displacement, velocity, pressure, von_mises, jacobian};
}

void WallModel::begin_record() {
  record_ = std::make_unique<Record>();
}

FaceRecord& WallModel::record() {
  return *record_;
}

std::optional<CycleStats> WallModel::record_step() {
  record_->add(step(), time(), problem_->measure_faces(solver_->displacement()));
  return std::nullopt;
}

} // namespace tearflow::run
