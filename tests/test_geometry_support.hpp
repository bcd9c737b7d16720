#pragma once
// Shared by the geometry tests: the parametric TBAD built once per test executable binary
// and cached on disk, because ctest runs every TEST in its own process and a build takes
// 10-20 s. The cache key is the spec and the modification time of the test executable, so a
// rebuilt library (which relinks the test) never reads an old mesh. Parallel test processes
// build into private directories and publish with an atomic rename.
#include <chrono>
#include <filesystem>
#include <string>
#include <system_error>
#include <unistd.h>

#include <fmt/format.h>

#include "core/file_layout.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/landmarks.hpp"
#include "geometry/tbad_builder.hpp"
#include "geometry/tbad_spec.hpp"

namespace tearflow::geometry::testing {

namespace fs = std::filesystem;

/// A private directory for one test process, removed with everything in it.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag)
      : path(fs::temp_directory_path() / fmt::format("tearflow-{}-{}", tag, ::getpid())) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

/// CI's element size: the default, 3 mm (about 15 s per model on one core).
constexpr double kCoarse = 3e-3;

struct CachedModel {
  mesh::Mesh mesh;
  Landmarks landmarks;
  fs::path dir;
};

/// `lumen_elements` < 0 keeps the spec's default.
inline TbadSpec variant_spec(const std::string& variant, double element_size,
                             int lumen_elements = -1) {
  TbadSpec s;
  apply_variant(s, variant);
  s.element_size = element_size;
  if (lumen_elements >= 0)
    s.lumen_elements = lumen_elements;
  return s;
}

inline CachedModel cached_tbad(const std::string& variant, double element_size,
                               int lumen_elements = -1) {
  std::error_code ec;
  const auto stamp = fs::last_write_time("/proc/self/exe", ec).time_since_epoch().count();
  const TbadSpec spec = variant_spec(variant, element_size, lumen_elements);
  const fs::path dir =
      fs::temp_directory_path() / fmt::format("tearflow-geometry-test-{}-{}-{:.2f}-n{}", stamp,
                                              variant, element_size * 1e3, spec.lumen_elements);
  if (!fs::is_regular_file(dir / GeometryFiles::kLandmarks, ec)) {
    const fs::path mine = dir.string() + fmt::format(".tmp{}", ::getpid());
    build_tbad(spec, mine);
    fs::rename(mine, dir, ec); // fails if another process won: use theirs
    if (ec)
      fs::remove_all(mine, ec);
  }
  return {read_fsi_mesh(dir / GeometryFiles::kMesh, 1e-3),
          read_landmarks(dir / GeometryFiles::kLandmarks), dir};
}

} // namespace tearflow::geometry::testing
