#pragma once
// `tearflow mri inflow` and `tearflow mri cine` (docs/mri.md): the 2D scans of the reference
// study, measured phase contrast into a case's inflow and targets, cine into lumen areas.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace tearflow::mri {

class Scan2dCommands {
public:
  explicit Scan2dCommands(CLI::App& mri); ///< registers `inflow` and `cine` under `mri`
  bool selected() const { return inflow_->parsed() || cine_->parsed(); }
  int run() const; ///< the chosen one; InputError for bad input

private:
  int inflow() const;
  int cine() const;

  CLI::App *inflow_ = nullptr, *cine_ = nullptr;
  std::string case_file_, inlet_, landmarks_, pressure_, venc_, output_;
  std::vector<std::string> outlets_, at_;
  bool no_background_ = false, no_unwrap_ = false, quiet_ = false;
  double lumen_fraction_ = 0.6;
};

} // namespace tearflow::mri
