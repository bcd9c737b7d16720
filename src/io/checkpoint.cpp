#include "io/checkpoint.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "core/digest.hpp"
#include "core/error.hpp"
#include "io/durable_file.hpp"

namespace tearflow::io {

namespace {

constexpr char kMagic[8] = {'T', 'F', 'C', 'K', 'P', 'T', '0', '3'};
constexpr char kMagicPrefix[6] = {'T', 'F', 'C', 'K', 'P', 'T'};

/// The file's bytes, built field by field.
class Writer {
public:
  template <typename T> void put(const T& v) {
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void put_string(const std::string& s) {
    put(static_cast<std::int32_t>(s.size()));
    bytes_.append(s);
  }
  void put_vector(const std::vector<double>& v) {
    put(static_cast<std::int64_t>(v.size()));
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
  }
  void append(const char* p, std::size_t n) { bytes_.append(p, n); }
  const std::string& bytes() const { return bytes_; }

private:
  std::string bytes_;
};

/// Reads fields from the file's bytes; every read is bounded by what is left, so a damaged
/// length is "truncated" or "corrupt", never an allocation of its size.
class Reader {
public:
  Reader(const std::string& bytes, std::size_t end, std::filesystem::path file)
      : bytes_(bytes), at_(sizeof kMagic), end_(end), file_(std::move(file)) {}

  template <typename T> T get(const char* field) {
    T v;
    need(sizeof(T), field);
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::string get_string(const char* field) {
    const auto n = get<std::int32_t>(field);
    if (n < 0)
      corrupt(field);
    need(static_cast<std::size_t>(n), field);
    std::string s = bytes_.substr(at_, static_cast<std::size_t>(n));
    at_ += static_cast<std::size_t>(n);
    return s;
  }
  std::vector<double> get_vector(const char* field) {
    const auto n = get<std::int64_t>(field);
    if (n < 0 || static_cast<std::uint64_t>(n) > (end_ - at_) / sizeof(double))
      corrupt(field);
    std::vector<double> v(static_cast<std::size_t>(n));
    std::memcpy(v.data(), bytes_.data() + at_, v.size() * sizeof(double));
    at_ += v.size() * sizeof(double);
    return v;
  }
  bool done() const { return at_ == end_; }
  [[noreturn]] void corrupt(const char* field) const {
    input_error("checkpoint '{}' is corrupt: its {} is out of range", file_.string(), field);
  }

private:
  void need(std::size_t n, const char* field) const {
    if (n > end_ - at_)
      input_error("checkpoint '{}' is truncated (it ends inside its {})", file_.string(), field);
  }
  const std::string& bytes_;
  std::size_t at_, end_;
  std::filesystem::path file_;
};

/// The first value of `v` that is not finite, as "value i", or empty.
std::string first_not_finite(const std::vector<double>& v) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      return fmt::format("value {} ({})", i, v[i]);
  return {};
}

} // namespace

void write_checkpoint(const std::filesystem::path& file, const Checkpoint& c) {
  Writer w;
  w.append(kMagic, sizeof kMagic);
  w.put(c.step);
  w.put(c.time);
  w.put(c.time_step);
  w.put(c.num_nodes);
  w.put(c.block);
  w.put(static_cast<std::int32_t>(c.fingerprint.size()));
  for (const auto& [part, value] : c.fingerprint) {
    w.put_string(part);
    w.put_string(value);
  }
  w.put_vector(c.solution);
  w.put_vector(c.derivative);
  w.put_vector(c.extra);
  w.put(static_cast<std::int32_t>(c.exact_operator));
  w.put(fnv1a(w.bytes().data(), w.bytes().size()));
  write_file_atomically(file, w.bytes()); // the old checkpoint stays until the new one is whole
}

Checkpoint read_checkpoint(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    input_error("no checkpoint '{}' to restart from", file.string());
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagicPrefix, 6) != 0)
    input_error("'{}' is not a tearflow checkpoint", file.string());
  if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    input_error("checkpoint '{}' is of an earlier format ({}), without the case's fingerprint "
                "and a checksum, so it cannot be checked; run from the start (without "
                "--restart)",
                file.string(), bytes.substr(6, 2));
  constexpr std::size_t kSum = sizeof(std::uint64_t);
  if (bytes.size() < sizeof kMagic + kSum)
    input_error("checkpoint '{}' is truncated", file.string());
  const std::size_t end = bytes.size() - kSum;
  std::uint64_t sum = 0;
  std::memcpy(&sum, bytes.data() + end, kSum);
  if (sum != fnv1a(bytes.data(), end))
    input_error("checkpoint '{}' is damaged: its checksum does not match its contents (cut "
                "short, or changed after it was written)",
                file.string());

  Reader r(bytes, end, file);
  Checkpoint c;
  c.step = r.get<std::int64_t>("step");
  c.time = r.get<double>("time");
  c.time_step = r.get<double>("time step");
  c.num_nodes = r.get<std::int64_t>("node count");
  c.block = r.get<std::int32_t>("unknowns per node");
  const auto parts = r.get<std::int32_t>("fingerprint");
  if (parts < 0 || parts > 64)
    r.corrupt("fingerprint");
  for (std::int32_t k = 0; k < parts; ++k) {
    std::string part = r.get_string("fingerprint");
    c.fingerprint.emplace_back(std::move(part), r.get_string("fingerprint"));
  }
  c.solution = r.get_vector("solution");
  c.derivative = r.get_vector("time derivative");
  c.extra = r.get_vector("0D states");
  c.exact_operator = r.get<std::int32_t>("Newton method") != 0;
  if (!r.done())
    r.corrupt("length");

  // The checksum says the bytes are the ones written; these say they describe a state.
  if (c.step < 0)
    r.corrupt("step");
  if (!(c.time_step > 0.0) || !std::isfinite(c.time_step))
    r.corrupt("time step");
  if (!std::isfinite(c.time) ||
      std::abs(c.time - static_cast<double>(c.step) * c.time_step) > 1e-9 * std::max(1.0, c.time))
    input_error("checkpoint '{}' is inconsistent: time {} s is not step {} x {} s", file.string(),
                c.time, c.step, c.time_step);
  if (c.num_nodes <= 0 || c.block <= 0 || c.block > 16 ||
      c.solution.size() !=
          static_cast<std::size_t>(c.num_nodes) * static_cast<std::size_t>(c.block) ||
      c.derivative.size() != c.solution.size())
    input_error("checkpoint '{}' is inconsistent: {} nodes x {} unknowns, but {} values and {} "
                "time derivatives",
                file.string(), c.num_nodes, c.block, c.solution.size(), c.derivative.size());
  for (const auto& [name, values] : {std::pair{"solution", &c.solution},
                                     {"time derivative", &c.derivative},
                                     {"0D states", &c.extra}})
    if (const std::string bad = first_not_finite(*values); !bad.empty())
      input_error("checkpoint '{}': its {} holds a value that is not finite ({})", file.string(),
                  name, bad);
  return c;
}

} // namespace tearflow::io
