#pragma once
// What a run records besides the fields: per step and named face the flow, mean pressure,
// area, reversed flow and (RCR outlets) distal pressure, written as faces.csv; per complete
// cardiac cycle the face statistics and the cycle-to-cycle change, written as cycles.json.
// Every rank holds the same record (the face measures are reduced over all ranks), so all
// of them agree on when a run has become periodic.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/file_layout.hpp"
#include "physics/fluid_problem.hpp"
#include "run/cycle_summary.hpp"

namespace tearflow::run {

struct FaceSample {
  physics::FaceMeasure measure;
  std::optional<double> distal_pressure; ///< RCR outlets only [Pa]
};

struct StepSample {
  int step = 0;
  double time = 0.0;
  std::vector<FaceSample> faces; ///< in the mesh's face order
};

/// A run's per-step record of its faces, whichever model made it: the file it is written to,
/// its text, and a restart's reload.
class FaceRecord {
public:
  virtual ~FaceRecord() = default;
  virtual std::filesystem::path file(const RunFiles& run) const = 0;
  virtual std::string csv() const = 0;       ///< the header and every row
  virtual std::string last_rows() const = 0; ///< the rows of the last step recorded
  /// Reads the file of an earlier run up to and including `last_step` (a restart).
  virtual void load_csv(const std::filesystem::path& file, int last_step) = 0;
  /// Every complete cardiac cycle, and cycles.json's content (none without a period).
  virtual const std::vector<run::CycleStats>& cycles() const = 0;
  virtual std::optional<nlohmann::json> cycles_record() const { return std::nullopt; }
};

/// The flow's record (faces.csv, cycles.json).
class RunRecord final : public FaceRecord {
public:
  /// `outlets` name the traction-outlet faces (flow split, periodicity); steps_per_cycle 0
  /// when the run has no cardiac period.
  /// `by_metrics`: the cycle-to-cycle change is metrics_change, else cycle_change.
  RunRecord(std::vector<std::string> outlets, int steps_per_cycle, double period,
            bool by_metrics = false);

  static constexpr const char* csv_header =
      "step,time_s,face,flow_m3_per_s,pressure_Pa,area_m2,reversed_flow_m3_per_s,"
      "distal_pressure_Pa";

  /// Appends the samples of one step (steps in increasing order). Returns the statistics of
  /// the cycle this step completes, if it completes one.
  std::optional<run::CycleStats> add(StepSample sample);

  /// Reads faces.csv of an earlier run up to and including `last_step` (a restart), and
  /// rebuilds the statistics of its complete cycles. InputError naming the file and line on
  /// a malformed row.
  void load_csv(const std::filesystem::path& file, int last_step) override;

  std::filesystem::path file(const RunFiles& run) const override { return run.faces_csv(); }
  std::string csv() const override;
  std::string last_rows() const override {
    return samples_.empty() ? std::string() : csv_rows(samples_.back());
  }
  std::optional<nlohmann::json> cycles_record() const override {
    if (steps_per_cycle_ == 0)
      return std::nullopt;
    return cycles_json();
  }
  /// The faces.csv rows of one step (no header).
  static std::string csv_rows(const StepSample& sample);
  const std::vector<StepSample>& samples() const { return samples_; }
  const std::vector<run::CycleStats>& cycles() const override { return cycles_; }
  nlohmann::json cycles_json() const { return run::cycles_to_json(period_, cycles_); }
  int steps_per_cycle() const { return steps_per_cycle_; }

private:
  run::CycleSamples cycle_samples(int cycle) const;

  std::vector<std::string> outlets_;
  int steps_per_cycle_ = 0;
  double period_ = 0.0;
  bool by_metrics_ = false;
  std::vector<StepSample> samples_;
  std::vector<run::CycleStats> cycles_;
};

} // namespace tearflow::run
