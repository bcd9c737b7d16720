#pragma once
// `tearflow mri synthesize | flow | compare | inflow | cine` (docs/mri.md): the command-line
// edge of src/mri.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace tearflow::mri {

struct Flow4D;
class Scan2dCommands;

class MriCommand {
public:
  explicit MriCommand(CLI::App& app); ///< registers `mri` and its subcommands on app
  ~MriCommand();
  bool selected() const { return command_->parsed(); }
  /// Runs the chosen subcommand; returns the exit code. InputError for bad input.
  int run() const;

private:
  int synthesize() const;
  int synthesize_from_run() const;
  int synthesize_slices_of_run() const; ///< 2D scans at the run's landmark planes
  void write_scan(const Flow4D& data, const std::filesystem::path& dir) const;
  int flow() const;
  int compare() const;
  /// Reads `input` and applies the corrections chosen, recording them in `report`.
  Flow4D load_corrected(const std::string& input, nlohmann::json& report) const;

  CLI::App *command_ = nullptr, *synthesize_ = nullptr, *flow_ = nullptr, *compare_ = nullptr;
  // synthesize
  std::string run_dir_;
  std::string voxel_ = "1.5mm", venc_ = "1m/s", radius_ = "10mm", tissue_ = "", format_ = "dicom";
  std::string size_, background_ = "0m/s";
  std::string scan_type_ = "4d", thickness_ = "6mm", fov_ = "80mm", case_file_;
  std::vector<std::string> at_;
  int frames_ = 20;
  double snr_ = 0.0, rotate_ = 0.0;
  unsigned seed_ = 1;
  // flow
  std::string input_, landmarks_, venc_override_, output_, align_, align_surface_;
  bool no_background_ = false, no_unwrap_ = false, quiet_ = false;
  int background_order_ = 2;
  double lumen_fraction_ = 0.6;
  // compare
  std::string simulation_, measured_, scan_;
  std::unique_ptr<Scan2dCommands> scans_; ///< `mri inflow`, `mri cine`
};

} // namespace tearflow::mri
