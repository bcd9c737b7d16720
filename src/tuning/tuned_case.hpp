#pragma once
// The written results of outlet tuning, for `tearflow tune` and the runs that correct their
// outlets at cycle ends (corrected_run.hpp): the tuned case file, its table of target vs
// achieved, and the steps as JSON.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "io/case.hpp"
#include "tuning/outlet_tuning.hpp"

namespace tearflow::tuning {

/// The case file with its tuned outlets: the same YAML document with the outlets' entries
/// replaced (comments are not kept), headed by `header`; relative file names are rewritten to
/// stay found from `out`'s folder.
std::string tuned_yaml(const std::filesystem::path& case_file, const io::Case& tuned,
                       const std::filesystem::path& out, const std::string& header);
/// The last step's target vs achieved, one row per pressure and split.
std::string table(const TuningResult& r, const TuningTargets& t);
/// Every step with its totals, achieved values, errors and distribution.
nlohmann::json to_json(const TuningResult& r, const TuningTargets& t);
/// `text` with "# " before every line.
std::string commented(const std::string& text);

} // namespace tearflow::tuning
