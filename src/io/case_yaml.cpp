#include "io/case_yaml.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "core/names.hpp"

namespace tearflow::io {

namespace {

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  const std::string best = nearest_name(word, candidates);
  return best.empty() ? "" : fmt::format(" (did you mean '{}'?)", best);
}

/// A finite number written in full (YAML's plain decimal and exponent forms), else nullopt.
std::optional<double> parse_double(std::string_view s) {
  if (!s.empty() && s.front() == '+')
    s.remove_prefix(1);
  double x = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(x))
    return std::nullopt;
  return x;
}

int line_of(const YAML::Node& node, int fallback) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? fallback : mark.line + 1;
}

} // namespace

std::filesystem::path resolve_path(const std::filesystem::path& dir, const std::string& written) {
  const std::filesystem::path p(written);
  return (p.is_absolute() ? p : dir / p).lexically_normal();
}

YAML::Node parse_yaml_file(const std::filesystem::path& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(file, ec))
    input_error("{}: case file not found (looked for {})", file.string(),
                fs::absolute(file, ec).string());
  if (fs::is_directory(file, ec))
    input_error("{}: is a directory; expected a YAML case file", file.string());
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  if (!in)
    input_error("{}: cannot read the case file", file.string());
  try {
    return YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    // ParserException and the few other errors yaml-cpp raises while building the document
    // (undefined alias, ...) carry the position of the problem.
    input_error("{}:{}: malformed YAML: {}", file.string(), e.mark.line + 1, e.msg);
  }
}

// ------------------------------------------------------------------------------------------

YamlValue::YamlValue(std::string file, YAML::Node root)
    : YamlValue(std::make_shared<const std::string>(std::move(file)), root, "", line_of(root, 1)) {}

YamlValue::YamlValue(std::shared_ptr<const std::string> file, YAML::Node node, std::string path,
                     int line)
    : file_(std::move(file)), node_(std::move(node)), path_(std::move(path)), line_(line) {}

std::string YamlValue::where() const {
  return path_.empty() ? fmt::format("{}:{}", *file_, line_)
                       : fmt::format("{}:{}: {}", *file_, line_, path_);
}

void YamlValue::fail(std::string_view what) const {
  throw InputError(fmt::format("{}: {}", where(), what));
}

void YamlValue::fail_expected(std::string_view expected) const {
  fail(fmt::format("expected {}, got {}", expected, describe()));
}

std::string YamlValue::describe() const {
  if (node_.IsScalar())
    return fmt::format("'{}'", node_.Scalar());
  if (node_.IsMap())
    return "a mapping";
  if (node_.IsSequence())
    return "a list";
  return "nothing";
}

// --- mappings ---

std::vector<std::pair<std::string, YamlValue>> YamlValue::entries() const {
  if (node_.IsNull())
    return {};
  if (!node_.IsMap())
    fail_expected("a mapping (key: value lines)");
  std::vector<std::pair<std::string, YamlValue>> out;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const int key_line = line_of(it->first, line_);
    if (!it->first.IsScalar())
      YamlValue(file_, it->first, path_, key_line).fail_expected("a key name");
    const std::string key = it->first.Scalar();
    const std::string path = path_.empty() ? key : path_ + "." + key;
    for (const auto& [seen, value] : out)
      if (seen == key)
        YamlValue(file_, it->second, path, key_line)
            .fail(fmt::format("key '{}' is given twice (first on line {})", key, value.line()));
    out.emplace_back(key, YamlValue(file_, it->second, path, key_line));
  }
  return out;
}

void YamlValue::check_keys(std::initializer_list<std::string_view> allowed,
                           std::initializer_list<std::string_view> elsewhere,
                           std::string_view elsewhere_reason) const {
  check_keys(std::vector<std::string_view>(allowed), std::vector<std::string_view>(elsewhere),
             elsewhere_reason);
}

void YamlValue::check_keys(const std::vector<std::string_view>& allowed,
                           const std::vector<std::string_view>& elsewhere,
                           std::string_view elsewhere_reason) const {
  const std::vector<std::string> names(allowed.begin(), allowed.end());
  for (const auto& [key, value] : entries()) {
    if (std::find(names.begin(), names.end(), key) != names.end())
      continue;
    if (std::find(elsewhere.begin(), elsewhere.end(), key) != elsewhere.end())
      value.fail(fmt::format("key '{}' does not apply here ({}); allowed keys: {}", key,
                             elsewhere_reason, fmt::join(names, ", ")));
    value.fail(fmt::format("unknown key '{}'{}; allowed keys{}: {}", key, did_you_mean(key, names),
                           path_.empty() ? " at the top level" : " in " + path_,
                           fmt::join(names, ", ")));
  }
}

bool YamlValue::has(std::string_view key) const {
  return get(key).has_value();
}

std::optional<YamlValue> YamlValue::get(std::string_view key) const {
  for (auto& [k, value] : entries())
    if (k == key)
      return value;
  return std::nullopt;
}

YamlValue YamlValue::require(std::string_view key, std::string_view expected) const {
  if (auto value = get(key))
    return *value;
  const std::string path = path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
  YamlValue(file_, YAML::Node(), path, line_)
      .fail(fmt::format("required key '{}' is missing; expected {}", key, expected));
}

// --- lists ---

std::vector<YamlValue> YamlValue::items() const {
  if (!node_.IsSequence())
    fail_expected("a list (lines starting with '- ', or [a, b])");
  std::vector<YamlValue> out;
  for (size_t i = 0; i < node_.size(); ++i) {
    const YAML::Node item = node_[i];
    // yaml-cpp marks an empty item at the next token, so fall back to the list's line.
    const int line = item.IsNull() ? line_ : line_of(item, line_);
    out.push_back(YamlValue(file_, item, fmt::format("{}[{}]", path_, i), line));
  }
  return out;
}

// --- scalars ---

std::optional<double> YamlValue::parse_number() const {
  if (!node_.IsScalar())
    return std::nullopt;
  // Quoted scalars ("1060") are strings in YAML; explicit !!int / !!float tags are numbers.
  const std::string& tag = node_.Tag();
  if (tag != "?" && tag != "tag:yaml.org,2002:float" && tag != "tag:yaml.org,2002:int")
    return std::nullopt;
  return parse_double(node_.Scalar());
}

void YamlValue::fail_number(std::string_view expected) const {
  const bool quoted_number =
      node_.IsScalar() && node_.Tag() == "!" && parse_double(node_.Scalar()).has_value();
  fail(fmt::format("expected {}, got {}{}", expected, describe(),
                   quoted_number ? " (quoted, so a string; remove the quotes)" : ""));
}

double YamlValue::number() const {
  if (auto x = parse_number())
    return *x;
  fail_number("a number");
}

double YamlValue::positive() const {
  const auto x = parse_number();
  if (!x || !(*x > 0.0))
    fail_number("a number > 0");
  return *x;
}

double YamlValue::non_negative() const {
  const auto x = parse_number();
  if (!x || !(*x >= 0.0))
    fail_number("a number >= 0");
  return *x;
}

double YamlValue::in_range(double lo, double hi) const {
  const auto x = parse_number();
  if (!x || *x < lo || *x > hi)
    fail_number(fmt::format("a number in [{}, {}]", lo, hi));
  return *x;
}

int YamlValue::integer(int min) const {
  const auto x = parse_number();
  if (!x || std::floor(*x) != *x || *x < min || *x > std::numeric_limits<int>::max())
    fail_number(fmt::format("an integer >= {}", min));
  return static_cast<int>(*x);
}

std::string YamlValue::text() const {
  if (!node_.IsScalar())
    fail_expected("a string");
  return node_.Scalar();
}

std::string YamlValue::choice(std::initializer_list<std::string_view> choices) const {
  return choice(std::vector<std::string_view>(choices));
}

std::string YamlValue::choice(const std::vector<std::string_view>& choices) const {
  const std::vector<std::string> names(choices.begin(), choices.end());
  if (!node_.IsScalar())
    fail_expected(fmt::format("one of {}", join_names(names)));
  const std::string s = node_.Scalar();
  if (std::find(names.begin(), names.end(), s) != names.end())
    return s;
  fail(fmt::format("unknown value '{}'{}; expected one of {}", s, did_you_mean(s, names),
                   join_names(names)));
}

std::vector<double> YamlValue::numbers() const {
  if (!node_.IsSequence())
    fail_expected("a list of numbers, like [0, 0.5, 1]");
  std::vector<double> out;
  for (const YamlValue& item : items())
    out.push_back(item.number());
  return out;
}

} // namespace tearflow::io
