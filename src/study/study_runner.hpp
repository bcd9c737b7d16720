#pragma once
// `tearflow study`: every variant of a study through the same stages, then one comparison:
//   geometry  `tearflow geometry tbad OPTIONS -o V/geometry` (or the imported model's folder)
//   tune      `tearflow tune V/case.yaml --targets V/targets.yaml -o V/tuned.yaml`
//   run       `tearflow run V/tuned.yaml [--restart]`, on the study's ranks
//   analyze   `tearflow analyze V/run --landmarks V/geometry/landmarks.json`
//   report    `tearflow report A/run B/run ... -o OUT/report.html [--png]`
// Each stage is a child process (its output goes to the screen with a "[V stage]" prefix and
// into OUT/study.log). A finished stage is recorded in OUT/study.json with the variant's
// fingerprint and its duration; running the study again skips what is recorded and still
// matches, continues an interrupted simulation from its checkpoint, and redoes a variant
// whose recipe, targets or case changed. OUT/summary.json collects the headline numbers.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "study/study_spec.hpp"

namespace tearflow::study {

class StudyRunner {
public:
  /// `tearflow`: the program the stages run (normally this one). `only`: the variants whose
  /// stages run (empty: all); the study-wide stages run once every variant's are done.
  StudyRunner(StudySpec spec, std::filesystem::path tearflow, std::vector<std::string> only = {});

  /// Runs what is left to do; returns 0, or the exit code of the stage that failed (after
  /// saying which and where its log is).
  int run();

private:
  struct Stage {
    const Variant* variant = nullptr; ///< nullptr: the study's report
    std::string name;
  };

  std::filesystem::path dir(const Variant& v) const { return spec_.output / v.name; }
  std::filesystem::path geometry_dir(const Variant& v) const;
  /// Every stage of the study, in order.
  std::vector<Stage> all_stages() const;
  /// The stages this invocation runs: the chosen variants' (`--only`), and the study-wide
  /// ones when no other variant has a stage left.
  std::vector<Stage> stages() const;
  bool chosen(const Variant& v) const;
  std::string stage_fingerprint(const Stage& s) const;
  bool finished(const Stage& s) const;
  void record(const Stage& s, double seconds);
  void forget_variant(const Variant& v); ///< its recipe changed: redo all its stages

  void write_case(const Variant& v) const;
  /// The case the variant's run ran with (run/tuned.yaml, tuned.yaml or case.yaml).
  std::filesystem::path ran_case(const Variant& v) const;
  /// rigid.yaml: the case its compliant run ended with (tuned outlets), without the wall.
  void write_rigid_case(const Variant& v) const;
  std::vector<std::string> command(const Stage& s) const;
  /// The reduced-order model's stages (rom_calibrate, rom_sweep) after the variants.
  std::vector<std::string> rom_command(const std::string& stage) const;
  /// Runs a child; returns its exit code. `stage` labels the lines.
  int execute(const Stage& s, const std::vector<std::string>& argv);
  void write_summary() const;
  /// The line before stage `index` of this invocation's `stages` (as run() listed them).
  void progress(const std::vector<Stage>& stages, std::size_t index) const;

  StudySpec spec_;
  std::filesystem::path tearflow_;
  std::vector<std::string> only_; ///< empty: every variant
  nlohmann::json record_;         ///< OUT/study.json
  double started_ = 0;            ///< wall clock of this invocation's start [s]
};

} // namespace tearflow::study
