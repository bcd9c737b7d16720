#pragma once
// Validated reading of YAML input files (used by load_case). A YamlValue is one node of the
// document together with its key path (`boundary_conditions[2].resistance`) and line, and
// every reader checks the node's type and range and throws an InputError of the form
//   case.yaml:14: boundary_conditions[2].resistance: expected a number > 0, got '0'
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/names.hpp"

namespace tearflow::io {

/// `written` taken from `dir` unless absolute, normalized (for paths in a case file).
std::filesystem::path resolve_path(const std::filesystem::path& dir, const std::string& written);

/// Parses a YAML file. InputError when it is missing, unreadable or malformed (with the
/// parser's line).
YAML::Node parse_yaml_file(const std::filesystem::path& file);

class YamlValue {
public:
  /// The document root of `file` (as the user named it, for messages).
  YamlValue(std::string file, YAML::Node root);

  const std::string& path() const { return path_; } ///< key path, "" at the root
  int line() const { return line_; }                ///< 1-based
  const std::string& file() const { return *file_; }
  /// "case.yaml:14: boundary_conditions[2].resistance" : the prefix of every message.
  std::string where() const;
  /// Throws InputError "where(): what".
  [[noreturn]] void fail(std::string_view what) const;
  /// Throws InputError "where(): expected <expected>, got <describe()>".
  [[noreturn]] void fail_expected(std::string_view expected) const;

  bool is_null() const { return node_.IsNull(); }
  bool is_map() const { return node_.IsMap(); }
  bool is_list() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }

  // --- mappings (a null value counts as an empty mapping) ---
  /// Fails unless this is a mapping whose keys are all in `allowed`, each given once. An
  /// unknown key is reported with the allowed keys and the nearest one if it looks like a
  /// typo; keys in `elsewhere` are reported as not applying here, with `elsewhere_reason`.
  void check_keys(std::initializer_list<std::string_view> allowed,
                  std::initializer_list<std::string_view> elsewhere = {},
                  std::string_view elsewhere_reason = "") const;
  void check_keys(const std::vector<std::string_view>& allowed,
                  const std::vector<std::string_view>& elsewhere = {},
                  std::string_view elsewhere_reason = "") const;
  /// Key/value pairs in document order; fails unless a mapping (or null).
  std::vector<std::pair<std::string, YamlValue>> entries() const;
  bool has(std::string_view key) const;
  std::optional<YamlValue> get(std::string_view key) const;
  /// The value of a required key; fails at this mapping's line, saying `expected`.
  YamlValue require(std::string_view key, std::string_view expected) const;

  // --- lists ---
  std::vector<YamlValue> items() const; ///< fails unless this is a list

  // --- scalars ---
  double number() const;                       ///< any finite number
  double positive() const;                     ///< > 0
  double non_negative() const;                 ///< >= 0
  double in_range(double lo, double hi) const; ///< in [lo, hi]
  int integer(int min) const;                  ///< an integer >= min
  std::string text() const;                    ///< any scalar, as written
  /// One of `choices` (exact spelling); otherwise fails listing them and the nearest one.
  std::string choice(std::initializer_list<std::string_view> choices) const;
  std::string choice(const std::vector<std::string_view>& choices) const;
  std::vector<double> numbers() const; ///< a list of finite numbers

  /// How the node reads in a message: 'text', a mapping, a list, nothing.
  std::string describe() const;

private:
  YamlValue(std::shared_ptr<const std::string> file, YAML::Node node, std::string path, int line);
  std::optional<double> parse_number() const;
  /// fail_expected, with a hint when the value is a quoted string.
  [[noreturn]] void fail_number(std::string_view expected) const;

  std::shared_ptr<const std::string> file_; ///< shared by all values of one document
  YAML::Node node_;
  std::string path_;
  int line_;
};

} // namespace tearflow::io
