#include "io/checkpoint.hpp"

#include <cstring>
#include <fstream>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tearflow::io {

namespace {
constexpr char magic[8] = {'T', 'F', 'C', 'K', 'P', 'T', '0', '2'};
constexpr char magic_01[8] = {'T', 'F', 'C', 'K', 'P', 'T', '0', '1'}; // before exact_operator

template <typename T> void put(std::ofstream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
void put_vector(std::ofstream& out, const std::vector<double>& v) {
  put(out, static_cast<std::int64_t>(v.size()));
  out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * 8));
}
template <typename T> void get(std::ifstream& in, T& v, const std::filesystem::path& file) {
  if (!in.read(reinterpret_cast<char*>(&v), sizeof(T)))
    input_error("checkpoint '{}' is truncated", file.string());
}
void get_vector(std::ifstream& in, std::vector<double>& v, const std::filesystem::path& file) {
  std::int64_t n = 0;
  get(in, n, file);
  if (n < 0 || n > (std::int64_t{1} << 34))
    input_error("checkpoint '{}' is corrupt", file.string());
  v.resize(static_cast<size_t>(n));
  if (!in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * 8)))
    input_error("checkpoint '{}' is truncated", file.string());
}
} // namespace

void write_checkpoint(const std::filesystem::path& file, const Checkpoint& c) {
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(magic, sizeof magic);
    put(out, c.step);
    put(out, c.time);
    put(out, c.num_nodes);
    put(out, c.block);
    put_vector(out, c.solution);
    put_vector(out, c.derivative);
    put_vector(out, c.extra);
    put(out, static_cast<std::int32_t>(c.exact_operator));
    out.flush();
    if (!out)
      input_error("cannot write checkpoint '{}'", tmp.string());
  }
  std::filesystem::rename(tmp, file); // atomic on POSIX: the old checkpoint stays until now
}

Checkpoint read_checkpoint(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    input_error("no checkpoint '{}' to restart from", file.string());
  char m[8];
  if (!in.read(m, sizeof m))
    input_error("'{}' is not a tearflow checkpoint", file.string());
  const bool version_01 = std::memcmp(m, magic_01, sizeof m) == 0;
  if (!version_01 && std::memcmp(m, magic, sizeof m) != 0)
    input_error("'{}' is not a tearflow checkpoint", file.string());
  Checkpoint c;
  get(in, c.step, file);
  get(in, c.time, file);
  get(in, c.num_nodes, file);
  get(in, c.block, file);
  get_vector(in, c.solution, file);
  get_vector(in, c.derivative, file);
  get_vector(in, c.extra, file);
  if (!version_01) {
    std::int32_t exact_operator = 0;
    get(in, exact_operator, file);
    c.exact_operator = exact_operator != 0;
  }
  if (c.solution.size() != static_cast<size_t>(c.num_nodes * c.block) ||
      c.derivative.size() != c.solution.size())
    input_error("checkpoint '{}' is inconsistent", file.string());
  return c;
}

} // namespace tearflow::io
