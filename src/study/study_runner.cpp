#include "study/study_runner.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/names.hpp"
#include "core/units.hpp"
#include "geometry/landmarks.hpp"
#include "geometry/sections.hpp"
#include "io/case_edit.hpp"
#include "io/case_yaml.hpp"
#include "io/output_lock.hpp"
#include "io/vtu_series.hpp"
#include "mesh/readers.hpp"
#include "rom/calibration.hpp"
#include "study/child_process.hpp"

namespace tearflow::study {

namespace {

using nlohmann::json;

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string minutes(double seconds) {
  const int s = static_cast<int>(seconds + 0.5);
  return s >= 3600 ? fmt::format("{}:{:02d}:{:02d}", s / 3600, s / 60 % 60, s % 60)
                   : fmt::format("{}:{:02d}", s / 60, s % 60);
}

std::vector<std::string> words(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string w; in >> w;)
    out.push_back(w);
  return out;
}

json read_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in)
    return nullptr;
  try {
    return json::parse(in);
  } catch (const json::exception&) {
    return nullptr;
  }
}

std::string key_of(const std::string& variant, const std::string& stage) {
  return variant.empty() ? stage : variant + "/" + stage;
}

} // namespace

StudyRunner::StudyRunner(StudySpec spec, std::filesystem::path tearflow,
                         std::vector<std::string> only)
    : spec_(std::move(spec)), tearflow_(std::move(tearflow)), only_(std::move(only)) {
  std::filesystem::create_directories(spec_.output);
  record_ = read_json(spec_.output / "study.json");
  if (!record_.is_object() || !record_.contains("stages"))
    record_ = json{{"study", spec_.file.string()}, {"stages", json::object()}};
}

std::filesystem::path StudyRunner::geometry_dir(const Variant& v) const {
  return v.model ? *v.model : dir(v) / "geometry";
}

namespace {

/// Targets whose 3D corrections happen in the run itself (tuning/corrected_run.hpp): the run
/// stage tunes, no tune stage.
bool tuned_in_run(const Variant& v) {
  return given(v.targets) && v.targets["in_run"] && v.targets["in_run"].as<std::string>() == "true";
}

} // namespace

/// The case the variant's run ran with: tuned in the run, tuned by `tune`, or as written.
std::filesystem::path StudyRunner::ran_case(const Variant& v) const {
  return tuned_in_run(v)    ? RunFiles{dir(v) / "run"}.tuned_case()
         : given(v.targets) ? dir(v) / "tuned.yaml"
                            : dir(v) / "case.yaml";
}

std::vector<StudyRunner::Stage> StudyRunner::all_stages() const {
  std::vector<Stage> out;
  for (const Variant& v : spec_.variants) {
    if (!v.model)
      out.push_back({&v, "geometry"});
    if (given(v.targets) && !tuned_in_run(v))
      out.push_back({&v, "tune"});
    out.push_back({&v, "run"});
    out.push_back({&v, "analyze"});
    out.push_back({&v, "pictures"});
    if (spec_.compare_rigid) {
      out.push_back({&v, "rigid_run"});
      out.push_back({&v, "rigid_analyze"});
      out.push_back({&v, "rigid_pictures"});
    }
  }
  if (spec_.rom_sweep) {
    out.push_back({nullptr, "rom_calibrate"});
    out.push_back({nullptr, "rom_sweep"});
  }
  out.push_back({nullptr, "report"});
  return out;
}

bool StudyRunner::chosen(const Variant& v) const {
  return only_.empty() || std::find(only_.begin(), only_.end(), v.name) != only_.end();
}

std::vector<StudyRunner::Stage> StudyRunner::stages() const {
  const std::vector<Stage> all = all_stages();
  // The study-wide stages use every variant's results: they wait while another variant has
  // a stage left.
  const bool others_done = std::all_of(all.begin(), all.end(), [&](const Stage& s) {
    return s.variant == nullptr || chosen(*s.variant) || finished(s);
  });
  std::vector<Stage> out;
  for (const Stage& s : all)
    if (s.variant != nullptr ? chosen(*s.variant) : others_done)
      out.push_back(s);
  return out;
}

std::string StudyRunner::stage_fingerprint(const Stage& s) const {
  if (s.variant != nullptr)
    return fingerprint(spec_, *s.variant);
  // (compare_rigid adds stages and runs to the report, and changes no variant's other stages)
  std::string all = std::string(spec_.png ? "png" : "") + (spec_.compare_rigid ? "rigid" : "");
  if (spec_.rom_sweep)
    all += fmt::format("rom{}/{}/{}", spec_.rom_sweep->entry, spec_.rom_sweep->exit,
                       spec_.rom_sweep->steps);
  for (const Variant& v : spec_.variants)
    all += fingerprint(spec_, v);
  return all;
}

bool StudyRunner::finished(const Stage& s) const {
  const std::string key = key_of(s.variant ? s.variant->name : "", s.name);
  const json& stages = record_["stages"];
  if (!stages.contains(key) || stages[key].value("fingerprint", "") != stage_fingerprint(s))
    return false;
  // A calibration made by an earlier tearflow for another network is refused by the stages
  // after it: calibrate again.
  return s.name != "rom_calibrate" ||
         rom::calibration_is_current(geometry_dir(spec_.variants.front()));
}

void StudyRunner::record(const Stage& s, double seconds) {
  record_["stages"][key_of(s.variant ? s.variant->name : "", s.name)] = {
      {"fingerprint", stage_fingerprint(s)}, {"seconds", seconds}};
  io::write_file_atomically(spec_.output / "study.json", record_.dump(2) + "\n");
}

void StudyRunner::forget_variant(const Variant& v) {
  json& stages = record_["stages"];
  for (auto it = stages.begin(); it != stages.end();)
    it = it.key().rfind(v.name + "/", 0) == 0 ? stages.erase(it) : std::next(it);
  std::filesystem::remove_all(dir(v) / "run"); // no restart from another recipe's state
  std::filesystem::remove_all(dir(v) / "rigid");
  io::write_file_atomically(spec_.output / "study.json", record_.dump(2) + "\n");
}

void StudyRunner::write_rigid_case(const Variant& v) const {
  const std::filesystem::path from = ran_case(v);
  YAML::Node root = YAML::Clone(io::parse_yaml_file(from));
  root["name"] = root["name"].as<std::string>() + "-rigid";
  root.remove("solid");
  root.remove("petsc_options"); // the compliant solver's
  root["mesh"]["region"] = "fluid";
  io::relocate_case_paths(root, from.parent_path()); // absolute: rigid.yaml is elsewhere
  root["output"]["directory"] = (dir(v) / "rigid").string();
  YAML::Emitter out;
  out << root;
  io::write_file_atomically(dir(v) / "rigid.yaml",
                            fmt::format("# Variant '{}' of study '{}' with rigid walls and the "
                                        "outlets of '{}', written by `tearflow study`.\n{}\n",
                                        v.name, spec_.name, from.string(), out.c_str()));
}

void StudyRunner::write_case(const Variant& v) const {
  std::filesystem::create_directories(dir(v));
  YAML::Node root = YAML::Clone(io::parse_yaml_file(spec_.case_file));
  const std::filesystem::path from = spec_.case_file.parent_path();
  root["name"] = spec_.name + "-" + v.name;
  for (const char* key : {"wall_file", "pipe"})
    root["mesh"].remove(key);
  root["mesh"]["file"] = GeometryFiles{geometry_dir(v)}.mesh().string();
  root["mesh"]["units"] = "mm";        // the geometry commands write millimetres
  io::relocate_case_paths(root, from); // absolute: the variant's case is elsewhere
  if (given(spec_.time)) {
    for (const char* key : {"steps", "end", "cycles", "periodicity"})
      root["time"].remove(key);
    for (const auto& entry : spec_.time)
      root["time"][entry.first.as<std::string>()] = YAML::Clone(entry.second);
  }
  root["output"]["directory"] = (dir(v) / "run").string();
  // Checkpoints are what an interrupted study continues from.
  if (!root["output"]["checkpoint_every"] || root["output"]["checkpoint_every"].as<int>(0) <= 0)
    root["output"]["checkpoint_every"] = 10;
  YAML::Emitter out;
  out << root;
  io::write_file_atomically(dir(v) / "case.yaml",
                            fmt::format("# Variant '{}' of study '{}' ({}), written by `tearflow "
                                        "study` from '{}'.\n{}\n",
                                        v.name, spec_.name, spec_.file.string(),
                                        spec_.case_file.string(), out.c_str()));
  if (given(v.targets)) {
    YAML::Emitter t;
    t << v.targets;
    io::write_file_atomically(dir(v) / "targets.yaml", std::string(t.c_str()) + "\n");
  }
}

std::vector<std::string> StudyRunner::command(const Stage& s) const {
  const std::string self = tearflow_.string();
  std::vector<std::string> parallel;
  if (spec_.ranks > 1) {
    std::string launcher = spec_.launcher;
    launcher.replace(launcher.find("{ranks}"), 7, std::to_string(spec_.ranks));
    parallel = words(launcher);
  }
  parallel.push_back(self);
  if (s.variant == nullptr && s.name != "report")
    return rom_command(s.name);
  if (s.variant == nullptr) {
    std::vector<std::string> argv{self, "report"};
    for (const Variant& v : spec_.variants)
      argv.push_back((dir(v) / "run").string());
    if (spec_.compare_rigid)
      for (const Variant& v : spec_.variants)
        argv.push_back((dir(v) / "rigid").string());
    argv.insert(argv.end(), {"-o", (spec_.output / "report.html").string()});
    if (spec_.rom_sweep)
      argv.insert(argv.end(), {"--rom-sweep", (spec_.output / "rom").string()});
    if (spec_.png)
      argv.push_back("--png");
    return argv;
  }
  const Variant& v = *s.variant;
  if (s.name == "geometry") {
    std::vector<std::string> argv{self, "geometry", "tbad", "-o", geometry_dir(v).string()};
    for (const auto& [option, value] : v.geometry) {
      argv.push_back("--" + option);
      for (const std::string& w : words(value))
        argv.push_back(w);
    }
    return argv;
  }
  if (s.name == "tune") {
    parallel.insert(parallel.end(),
                    {"tune", (dir(v) / "case.yaml").string(), "--targets",
                     (dir(v) / "targets.yaml").string(), "-o", (dir(v) / "tuned.yaml").string()});
    return parallel;
  }
  if (s.name == "run") {
    if (tuned_in_run(v))
      parallel.insert(parallel.end(), {"run", (dir(v) / "case.yaml").string(), "--targets",
                                       (dir(v) / "targets.yaml").string()});
    else
      parallel.insert(parallel.end(), {"run", ran_case(v).string()});
    if (std::filesystem::exists(RunFiles{dir(v) / "run"}.checkpoint()))
      parallel.push_back("--restart"); // an interrupted run continues
    return parallel;
  }
  if (s.name == "rigid_run") {
    parallel.insert(parallel.end(), {"run", (dir(v) / "rigid.yaml").string()});
    if (std::filesystem::exists(RunFiles{dir(v) / "rigid"}.checkpoint()))
      parallel.push_back("--restart");
    return parallel;
  }
  if (s.name == "pictures" || s.name == "rigid_pictures")
    // The report's "Flow patterns" (docs/analysis.md): peak systole, mid-diastole, the cycle's
    // streamlines animated; the study's views and scales are the command's defaults, so the
    // variants' pictures compare.
    return {self,
            "pictures",
            (dir(v) / (s.name == "pictures" ? "run" : "rigid")).string(),
            "--model",
            geometry_dir(v).string(),
            "--animate",
            "--quiet"};
  const std::string run = s.name == "rigid_analyze" ? "rigid" : "run";
  // The case that ran, for the conservative flux (docs/analysis.md).
  const std::filesystem::path ran = s.name == "rigid_analyze" ? dir(v) / "rigid.yaml" : ran_case(v);
  return {self,
          "analyze",
          (dir(v) / run).string(),
          "--landmarks",
          GeometryFiles{geometry_dir(v)}.landmarks().string(),
          "--case",
          ran.string()};
}

std::vector<std::string> StudyRunner::rom_command(const std::string& stage) const {
  // The first variant's model is the reduced-order model's geometry; the other variants are
  // its tear-size variants (their own models give their tears' areas).
  const Variant& first = spec_.variants.front();
  const std::string model = geometry_dir(first).string();
  if (stage == "rom_calibrate") {
    std::vector<std::string> argv{tearflow_.string(), "rom", "calibrate", model};
    for (const Variant& v : spec_.variants) {
      argv.insert(argv.end(), {"--run", (dir(v) / "run").string(), "--case", ran_case(v).string(),
                               "--run-model", geometry_dir(v).string()});
      if (spec_.compare_rigid)
        argv.insert(argv.end(),
                    {"--run", (dir(v) / "rigid").string(), "--case",
                     (dir(v) / "rigid.yaml").string(), "--run-model", geometry_dir(v).string()});
    }
    return argv;
  }
  std::vector<std::string> argv{tearflow_.string(),
                                "rom",
                                "sweep",
                                model,
                                "--case",
                                ran_case(first).string(),
                                "--entry",
                                spec_.rom_sweep->entry,
                                "--exit",
                                spec_.rom_sweep->exit,
                                "--steps",
                                std::to_string(spec_.rom_sweep->steps),
                                "-o",
                                (spec_.output / "rom").string()};
  for (const Variant& v : spec_.variants) { // the 3D variants marked on the maps
    const geometry::Landmarks lm =
        geometry::read_landmarks(GeometryFiles{geometry_dir(v)}.landmarks());
    double entry = 0, exit = 0;
    for (const geometry::TearLandmark& t : lm.tears) {
      if (t.name == "entry")
        entry = t.area * 1e6; // mm^2
      if (t.name == "exit")
        exit = t.area * 1e6;
    }
    if (entry > 0 && exit > 0)
      argv.insert(argv.end(), {"--mark", fmt::format("{}={:.6g}:{:.6g}", v.name, entry, exit)});
  }
  return argv;
}

int StudyRunner::execute(const Stage& s, const std::vector<std::string>& argv) {
  const std::string label =
      s.variant ? fmt::format("[{} {}] ", s.variant->name, s.name) : fmt::format("[{}] ", s.name);
  std::ofstream log(spec_.output / "study.log", std::ios::app);
  std::string line_of_command;
  for (const std::string& a : argv)
    line_of_command += (line_of_command.empty() ? "" : " ") + a;
  log << label << "$ " << line_of_command << "\n";
  return run_child(argv, spec_.output, [&](const std::string& line) {
    fmt::print("{}{}\n", label, line);
    std::fflush(stdout);
    log << label << line << "\n";
    log.flush();
  });
}

void StudyRunner::progress(const std::vector<Stage>& all, std::size_t index) const {
  // ETA: the remaining stages at the mean duration recorded for their kind.
  std::map<std::string, std::pair<double, int>> spent; // stage kind -> (seconds, count)
  for (const auto& [key, entry] : record_["stages"].items()) {
    const std::string kind = key.substr(key.find('/') + 1);
    spent[kind].first += entry.value("seconds", 0.0);
    spent[kind].second += 1;
  }
  double eta = 0;
  bool known = true;
  for (std::size_t i = index; i < all.size(); ++i) {
    if (finished(all[i]))
      continue;
    const auto it = spent.find(all[i].name);
    if (it != spent.end())
      eta += it->second.first / it->second.second;
    else if (all[i].variant == nullptr)
      eta += spec_.png ? 60.0 : 5.0; // the report: seconds, a minute with Chromium's figures
    else
      known = false;
  }
  const Stage& s = all[index];
  fmt::print("study '{}': stage {}/{}: {}{} (elapsed {}, {})\n", spec_.name, index + 1, all.size(),
             s.variant ? s.variant->name + " " : "", s.name, minutes(now() - started_),
             known ? "ETA " + minutes(eta) : std::string("ETA after the first variant"));
  std::fflush(stdout);
}

int StudyRunner::run() {
  started_ = now();
  // One study at a time in this folder (io/output_lock.hpp).
  const io::OutputLock lock(spec_.output, {".study.lock", "tearflow study", "the study's output",
                                           fmt::format("tearflow study {}", spec_.file.string()),
                                           "give this study another `output`"});
  if (!lock.taken_over().empty())
    fmt::print("study '{}': its output's lock was left by a study that ended without releasing "
               "it ({}): killed? Taken over\n",
               spec_.name, lock.taken_over());
  for (const Variant& v : spec_.variants) {
    if (!chosen(v))
      continue;
    bool changed = false;
    for (const auto& [key, entry] : record_["stages"].items())
      changed = changed || (key.rfind(v.name + "/", 0) == 0 &&
                            entry.value("fingerprint", "") != fingerprint(spec_, v));
    if (changed) {
      fmt::print("study '{}': variant {} changed since it ran (recipe, targets, case or time): "
                 "running it again\n",
                 spec_.name, v.name);
      forget_variant(v);
    }
    write_case(v);
  }
  const std::vector<Stage> all = stages();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Stage& s = all[i];
    if (finished(s))
      continue;
    // The study-wide stages after this one (the ROM's, the report) use what it makes: they
    // run again, also when this study is interrupted and run once more.
    // (With --only they may not be in this invocation's list: they are forgotten all the same.)
    const std::vector<Stage> every = all_stages();
    const auto here = std::find_if(every.begin(), every.end(), [&](const Stage& e) {
      return e.variant == s.variant && e.name == s.name;
    });
    std::size_t erased = 0;
    for (auto later = here + 1; later < every.end(); ++later)
      if (later->variant == nullptr)
        erased += record_["stages"].erase(key_of("", later->name));
    if (erased > 0)
      io::write_file_atomically(spec_.output / "study.json", record_.dump(2) + "\n");
    progress(all, i);
    if (s.name == "rigid_run")
      write_rigid_case(*s.variant);
    const double t0 = now();
    const int code = execute(s, command(s));
    // `tune` exits with 1 when the targets are not met within the tolerances: the best
    // outlets found are written and the study goes on (the report shows target vs achieved).
    const bool not_met = s.name == "tune" && code == 1;
    if (code != 0 && !not_met) {
      fmt::print(stderr,
                 "study '{}': {} {} failed (exit code {}); its output is in '{}'. Run the same "
                 "command again to continue from there.\n",
                 spec_.name, s.variant ? "variant " + s.variant->name + ":" : "", s.name, code,
                 (spec_.output / "study.log").string());
      return code;
    }
    if (not_met)
      fmt::print("study '{}': {}: tuning targets not met within the tolerances; going on with "
                 "the best outlets found (see '{}')\n",
                 spec_.name, s.variant->name, (dir(*s.variant) / "tuned.yaml").string());
    if ((s.name == "analyze" || s.name == "rigid_analyze") &&
        given(s.variant->targets)) // the report shows target vs achieved
      std::filesystem::copy_file(dir(*s.variant) / "targets.yaml",
                                 dir(*s.variant) / (s.name == "analyze" ? "run" : "rigid") /
                                     "targets.yaml",
                                 std::filesystem::copy_options::overwrite_existing);
    record(s, now() - t0);
  }
  if (all.empty() || all.back().variant != nullptr) { // --only, with other variants left
    const std::vector<Stage> every = all_stages();
    std::vector<std::string> waiting;
    for (const Variant& v : spec_.variants)
      if (std::any_of(every.begin(), every.end(),
                      [&](const Stage& s) { return s.variant == &v && !finished(s); }))
        waiting.push_back(v.name);
    fmt::print("study '{}': the chosen variants are done in {}; the study-wide stages (report, "
               "summary{}) wait for {}: run the study without --only once they are done\n",
               spec_.name, minutes(now() - started_),
               spec_.rom_sweep ? ", reduced-order model" : "", join_names(waiting, "and"));
    return 0;
  }
  write_summary();
  fmt::print("study '{}' done in {}: report '{}', summary '{}'\n", spec_.name,
             minutes(now() - started_), (spec_.output / "report.html").string(),
             (spec_.output / "summary.json").string());
  return 0;
}

void StudyRunner::write_summary() const {
  json variants = json::object();
  for (const Variant& v : spec_.variants) {
    json entry;
    const geometry::Landmarks landmarks =
        geometry::read_landmarks(GeometryFiles{geometry_dir(v)}.landmarks());
    // The tear areas as the mesh has them (the hole in the flap's mid-plane), beside the
    // areas the landmarks declare (the recipe's, for a built-in model).
    const mesh::Mesh mesh = mesh::read_gmsh(GeometryFiles{geometry_dir(v)}.mesh(), units::mm);
    for (const geometry::TearLandmark& t : landmarks.tears) {
      entry["tear_area_mm2"][t.name] = geometry::tear_area(mesh, t) / (units::mm * units::mm);
      entry["tear_area_declared_mm2"][t.name] = t.area / (units::mm * units::mm);
    }
    const json metrics = read_json(RunFiles{dir(v) / "run"}.metrics_json());
    // Every metric the analysis wrote, as it wrote it: a new metric appears here without a
    // list to keep (issue 24).
    if (metrics.is_object())
      entry.update(metrics);
    if (spec_.compare_rigid) { // the rigid-wall counterpart's metrics
      const json rigid = read_json(RunFiles{dir(v) / "rigid"}.metrics_json());
      if (rigid.is_object())
        entry["rigid"] = rigid;
    }
    const json tuning = read_json(tuned_in_run(v) ? RunFiles{dir(v) / "run"}.tuning_json()
                                                  : dir(v) / "tuned.tuning.json");
    if (tuning.is_object()) {
      entry["tuning"] = tuning;
      entry["tuning"].erase("run_state"); // the restart's copy of the steps
    }
    // What ran: the wall model and the cycles with their change from the previous one.
    entry["wall"] = io::parse_yaml_file(dir(v) / "case.yaml")["solid"] ? "fsi" : "rigid";
    const json cycles = read_json(RunFiles{dir(v) / "run"}.cycles_json());
    if (cycles.is_object() && cycles.contains("cycles")) {
      entry["cycles_run"] = cycles["cycles"].size();
      if (!cycles["cycles"].empty())
        entry["periodicity_last_change"] = cycles["cycles"].back()["change_from_previous"];
    }
    variants[v.name] = entry;
  }
  io::write_file_atomically(
      spec_.output / "summary.json",
      json{{"study", spec_.name}, {"variants", variants}, {"stages", record_["stages"]}}.dump(2) +
          "\n");
}

} // namespace tearflow::study
