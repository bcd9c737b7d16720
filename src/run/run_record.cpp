#include "run/run_record.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tearflow::run {

RunRecord::RunRecord(std::vector<std::string> outlets, int steps_per_cycle, double period,
                     bool by_metrics)
    : outlets_(std::move(outlets)), steps_per_cycle_(steps_per_cycle), period_(period),
      by_metrics_(by_metrics) {}

std::optional<run::CycleStats> RunRecord::add(StepSample sample) {
  const int step = sample.step;
  samples_.push_back(std::move(sample));
  const int n = steps_per_cycle_;
  if (n == 0 || step == 0 || step % n != 0)
    return std::nullopt;
  const int cycle = step / n - 1;
  // The cycle is complete only if its first sample is recorded (not so after a restart
  // from a checkpoint whose faces.csv lost rows).
  if (samples_.size() < static_cast<size_t>(n + 1) ||
      samples_[samples_.size() - n - 1].step != step - n)
    return std::nullopt;
  const run::CycleSamples current = cycle_samples(cycle);
  run::CycleStats stats = run::summarize_cycle(current);
  if (samples_.size() >= static_cast<size_t>(2 * n + 1) &&
      samples_[samples_.size() - 2 * n - 1].step == step - 2 * n)
    stats.change = by_metrics_
                       ? run::metrics_change(run::summarize_cycle(cycle_samples(cycle - 1)), stats)
                       : run::cycle_change(cycle_samples(cycle - 1), current);
  cycles_.push_back(stats);
  return stats;
}

run::CycleSamples RunRecord::cycle_samples(int cycle) const {
  const int n = steps_per_cycle_;
  const int first = cycle * n;
  const auto begin = std::find_if(samples_.begin(), samples_.end(),
                                  [&](const StepSample& s) { return s.step == first; });
  run::CycleSamples c;
  c.cycle = cycle;
  for (size_t f = 0; f < begin->faces.size(); ++f) {
    const std::string& name = begin->faces[f].measure.face;
    c.faces.push_back(
        {name, std::find(outlets_.begin(), outlets_.end(), name) != outlets_.end(), {}, {}, {}});
  }
  for (auto it = begin; it != begin + n + 1; ++it) {
    c.time.push_back(it->time);
    for (size_t f = 0; f < it->faces.size(); ++f) {
      const physics::FaceMeasure& m = it->faces[f].measure;
      c.faces[f].flow.push_back(m.flow);
      c.faces[f].pressure.push_back(m.pressure);
      c.faces[f].reversed.push_back(m.reversed);
    }
  }
  return c;
}

std::string RunRecord::csv() const {
  std::string text = std::string(csv_header) + "\n";
  for (const StepSample& s : samples_)
    text += csv_rows(s);
  return text;
}

std::string RunRecord::csv_rows(const StepSample& s) {
  std::string text;
  for (const FaceSample& f : s.faces) {
    const physics::FaceMeasure& m = f.measure;
    // Shortest round-trip text: a restart reads back the very numbers the run held, so its
    // cycle statistics and periodicity test repeat the uninterrupted run's.
    text +=
        fmt::format("{},{},{},{},{},{},{},{}\n", s.step, s.time, m.face, m.flow, m.pressure, m.area,
                    m.reversed, f.distal_pressure ? fmt::format("{}", *f.distal_pressure) : "");
  }
  return text;
}

void RunRecord::load_csv(const std::filesystem::path& file, int last_step) {
  std::ifstream in(file);
  if (!in)
    input_error("cannot read '{}' to continue its face record", file.string());
  std::string line;
  std::getline(in, line);
  if (line != csv_header)
    input_error("{}:1: expected the header '{}'", file.string(), csv_header);
  samples_.clear();
  cycles_.clear();
  std::vector<StepSample> rows;
  for (int number = 2; std::getline(in, line); ++number) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');)
      cells.push_back(cell);
    if (cells.size() == 7 && !line.empty() && line.back() == ',')
      cells.emplace_back();
    try {
      if (cells.size() != 8)
        throw std::invalid_argument("8 columns");
      const int step = std::stoi(cells[0]);
      if (step > last_step)
        break;
      if (rows.empty() || rows.back().step != step)
        rows.push_back({step, std::stod(cells[1]), {}});
      FaceSample f;
      f.measure = {cells[2], std::stod(cells[3]), std::stod(cells[4]), std::stod(cells[5]),
                   std::stod(cells[6])};
      if (!cells[7].empty())
        f.distal_pressure = std::stod(cells[7]);
      rows.back().faces.push_back(f);
    } catch (const std::exception&) {
      // Rows are appended as steps end: a last line without its newline was cut short by a
      // kill or a full disk, after the checkpoint's rewrite of the whole file (so after the
      // checkpoint's step), and is dropped with the rows it would have ended.
      if (in.eof())
        break;
      input_error("{}:{}: expected {} numbers, got '{}'", file.string(), number, csv_header, line);
    }
  }
  for (StepSample& s : rows)
    add(std::move(s));
}

} // namespace tearflow::run
