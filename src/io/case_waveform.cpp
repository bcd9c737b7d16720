#include "io/case_waveform.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"

namespace tearflow::io {

namespace {

namespace fs = std::filesystem;

double value_scale(const std::optional<YamlValue>& units, const Quantity& q) {
  return units ? q.scale(units->text(), units->where()) : q.scale(q.si_unit, "");
}

double time_scale(const std::optional<YamlValue>& time_units) {
  if (!time_units)
    return 1.0;
  return time_units->choice({"s", "ms"}) == "s" ? 1.0 : 1e-3;
}

/// Runs a waveform file reader; its errors (which name the waveform file and its line) are
/// prefixed with the case file's position of the `file` key.
template <typename Read> bc::Waveform read_waveform_file(const YamlValue& key, Read read) {
  try {
    return read();
  } catch (const InputError& e) {
    key.fail(e.what());
  }
}

bc::Waveform read_waveform_from_file(const YamlValue& v, const Quantity& q,
                                     const fs::path& case_dir) {
  v.check_keys({"file", "format", "time_units", "units", "period", "sign"}, {"times", "values"},
               "give either file or times/values");
  const YamlValue file = *v.get("file");
  const fs::path path = resolve_path(case_dir, file.text());
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    file.fail(fmt::format("waveform file not found: {}", path.string()));
  const double scale = value_scale(v.get("units"), q);

  const std::string format = v.has("format") ? v.get("format")->choice({"csv", "simvascular"})
                             : path.extension() == ".flow" ? "simvascular"
                                                           : "csv";
  if (format == "simvascular") {
    if (auto x = v.get("time_units"))
      x->fail("a SimVascular .flow file is in seconds; time_units applies to format csv");
    if (auto x = v.get("period"))
      x->fail("the last sample of a SimVascular .flow file closes the period; period applies "
              "to format csv");
    return read_waveform_file(file, [&] { return bc::read_simvascular_flow(path, scale); });
  }
  const double ts = time_scale(v.get("time_units"));
  // Without a period, the last sample closes it (read_waveform_csv's period 0).
  const double period = v.has("period") ? v.get("period")->positive() * ts : 0.0;
  return read_waveform_file(file, [&] { return bc::read_waveform_csv(path, ts, scale, period); });
}

bc::Waveform read_waveform_samples(const YamlValue& v, const Quantity& q) {
  v.check_keys({"times", "values", "time_units", "units", "period", "sign"}, {"file", "format"},
               "give either file or times/values");
  const YamlValue times = v.require("times", "the sample times over one period, a list");
  const YamlValue values = v.require("values", "the sampled values, a list");
  std::vector<double> t = times.numbers();
  std::vector<double> x = values.numbers();
  if (x.size() != t.size())
    values.fail(
        fmt::format("{} values for {} times; expected one value per time", x.size(), t.size()));
  const double ts = time_scale(v.get("time_units"));
  const double scale = value_scale(v.get("units"), q);
  for (double& ti : t)
    ti *= ts;
  for (double& xi : x)
    xi *= scale;
  // Without a period, the last sample closes it.
  const double period = v.has("period") ? v.get("period")->positive() * ts
                        : t.size() >= 2 ? t.back() - t.front()
                                        : 0.0;
  return bc::Waveform::periodic(std::move(t), std::move(x), period, v.where());
}

} // namespace

const Quantity kFlow{"flow", "m3/s", units::flow_scale};
const Quantity kPressure{"pressure", "Pa", units::pressure_scale};

bc::Waveform read_case_waveform(const YamlValue& v, const std::optional<YamlValue>& sibling_units,
                                const Quantity& q, const fs::path& case_dir) {
  if (v.is_scalar())
    return bc::Waveform::constant(v.number() * value_scale(sibling_units, q));
  if (!v.is_map())
    v.fail_expected(fmt::format("a constant {} (a number), or a mapping with file or "
                                "times/values",
                                q.name));
  if (sibling_units)
    sibling_units->fail(fmt::format("units applies to a constant {0}; for a {0} mapping give "
                                    "the unit inside it ({0}: {{..., units: ...}})",
                                    q.name));
  if (v.has("file") && (v.has("times") || v.has("values")))
    (v.has("times") ? *v.get("times") : *v.get("values"))
        .fail("give either file or times/values, not both");
  if (!v.has("file") && !v.has("times") && !v.has("values"))
    v.fail("expected file (a CSV or SimVascular .flow file) or times and values (samples "
           "over one period)");
  double sign = 1.0;
  if (auto s = v.get("sign")) {
    sign = s->number();
    if (sign != 1.0 && sign != -1.0)
      s->fail_expected("1 or -1");
  }
  const bc::Waveform w =
      v.has("file") ? read_waveform_from_file(v, q, case_dir) : read_waveform_samples(v, q);
  return sign == 1.0 ? w : w.scaled(sign);
}

} // namespace tearflow::io
