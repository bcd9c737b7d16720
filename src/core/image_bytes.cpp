// Image files that ITK reads wrong (core/image_bytes.hpp): the bytes present against the
// header's; NIfTI's values that are not numbers, read again from the file.
#include "core/image_bytes.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <zlib.h>

#include "core/error.hpp"

namespace tearflow {

namespace fs = std::filesystem;

namespace {

/// NIfTI (.nii or .nii.gz): the bytes the file holds (decompressed) against its header's
/// vox_offset plus the image's bytes.
std::pair<std::uint64_t, std::uint64_t> nifti_bytes(const fs::path& file, std::uint64_t image) {
  gzFile f = gzopen(file.c_str(), "rb"); // reads an uncompressed file as it is
  if (f == nullptr)
    input_error("'{}': cannot be opened", file.string());
  std::vector<unsigned char> buffer(1 << 20);
  std::vector<unsigned char> header;
  std::uint64_t total = 0;
  for (int n; (n = gzread(f, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0;) {
    if (header.size() < 544)
      header.insert(header.end(), buffer.begin(), buffer.begin() + std::min(n, 544));
    total += static_cast<std::uint64_t>(n);
  }
  gzclose(f); // a gzip stream cut short ends the reads early: the count says so below
  std::uint64_t offset = 352;
  std::int32_t size = 0;
  if (header.size() >= 4)
    std::memcpy(&size, header.data(), 4);
  if (size == 348 && header.size() >= 112) { // NIfTI-1: float vox_offset at byte 108
    float v = 0.0f;
    std::memcpy(&v, header.data() + 108, 4);
    offset = static_cast<std::uint64_t>(std::max(v, 348.0f));
  } else if (size == 540 && header.size() >= 176) { // NIfTI-2: int64 at byte 168
    std::int64_t v = 0;
    std::memcpy(&v, header.data() + 168, 8);
    offset = static_cast<std::uint64_t>(std::max<std::int64_t>(v, 540));
  }
  return {total, offset + image};
}

/// MetaImage (.mha with its data, or .mhd beside a data file): the data bytes present
/// against the header's (CompressedDataSize when compressed, else the image's bytes).
std::pair<std::uint64_t, std::uint64_t> meta_bytes(const fs::path& file, std::uint64_t image) {
  std::ifstream in(file, std::ios::binary);
  std::string line, data_file;
  std::uint64_t needed = image;
  bool compressed = false;
  while (std::getline(in, line)) {
    const size_t eq = line.find('=');
    if (eq == std::string::npos)
      continue;
    auto trim = [](std::string t) {
      t.erase(0, t.find_first_not_of(" \t\r"));
      t.erase(t.find_last_not_of(" \t\r") + 1);
      return t;
    };
    const std::string key = trim(line.substr(0, eq)), value = trim(line.substr(eq + 1));
    if (key == "CompressedData")
      compressed = value == "True" || value == "true";
    if (key == "CompressedDataSize" && compressed)
      needed = std::stoull(value);
    if (key == "ElementDataFile") {
      data_file = value;
      break; // the last header line
    }
  }
  if (data_file == "LOCAL")
    return {fs::file_size(file) - static_cast<std::uint64_t>(in.tellg()), needed};
  return {fs::file_size(file.parent_path() / data_file), needed};
}

/// What the NIfTI header says of the voxels: where they start, their type, byte order.
struct NiftiVoxels {
  std::uint64_t offset = 352;
  int datatype = 0;     ///< NIFTI_TYPE_FLOAT32 16, NIFTI_TYPE_FLOAT64 64, ...
  bool swapped = false; ///< the file's byte order is not this machine's
};

template <typename T> T field(const std::vector<unsigned char>& header, std::size_t at, bool swap) {
  T v{};
  std::memcpy(&v, header.data() + at, sizeof(T));
  if (swap) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

/// The header's voxel layout, NIfTI-1 (348 bytes) or NIfTI-2 (540), either byte order;
/// datatype 0 when the header is neither.
NiftiVoxels nifti_voxels(const std::vector<unsigned char>& header) {
  NiftiVoxels v;
  if (header.size() < 348)
    return v;
  for (const bool swap : {false, true}) {
    const auto size = field<std::int32_t>(header, 0, swap);
    if (size == 348) {
      v.offset = static_cast<std::uint64_t>(std::max(field<float>(header, 108, swap), 348.0f));
      v.datatype = field<std::int16_t>(header, 70, swap);
    } else if (size == 540 && header.size() >= 540) {
      v.offset = static_cast<std::uint64_t>(
          std::max<std::int64_t>(field<std::int64_t>(header, 168, swap), 540));
      v.datatype = field<std::int16_t>(header, 12, swap);
    } else {
      continue;
    }
    v.swapped = swap;
    return v;
  }
  return v;
}

/// Calls f(index, value) for each voxel value of type T of the stream `f`, from its current
/// position, for the first `count` values.
template <typename T, typename F>
void for_each_value(gzFile file, bool swap, std::uint64_t count, F&& f) {
  std::vector<unsigned char> buffer((1 << 20) * sizeof(T));
  std::uint64_t index = 0;
  std::size_t kept = 0; // bytes of a value split across two reads
  for (int n; index < count && (n = gzread(file, buffer.data() + kept,
                                           static_cast<unsigned>(buffer.size() - kept))) > 0;) {
    const std::size_t bytes = kept + static_cast<std::size_t>(n);
    const std::size_t values = bytes / sizeof(T);
    for (std::size_t i = 0; i < values && index < count; ++i, ++index) {
      T v;
      unsigned char b[sizeof(T)];
      std::memcpy(b, buffer.data() + i * sizeof(T), sizeof(T));
      if (swap)
        std::reverse(b, b + sizeof(T));
      std::memcpy(&v, b, sizeof(T));
      f(index, v);
    }
    kept = bytes - values * sizeof(T);
    std::memmove(buffer.data(), buffer.data() + values * sizeof(T), kept);
  }
}

} // namespace

std::uint64_t restore_nifti_non_finite(const fs::path& file, float* pixels, std::uint64_t count) {
  gzFile f = gzopen(file.c_str(), "rb"); // reads an uncompressed file as it is
  if (f == nullptr)
    input_error("'{}': cannot be opened", file.string());
  std::vector<unsigned char> header(544);
  const int n = gzread(f, header.data(), static_cast<unsigned>(header.size()));
  header.resize(static_cast<std::size_t>(std::max(n, 0)));
  const NiftiVoxels layout = nifti_voxels(header);
  std::uint64_t restored = 0;
  auto restore = [&](std::uint64_t index, auto value) {
    if (!std::isfinite(value)) {
      pixels[index] = static_cast<float>(value);
      ++restored;
    }
  };
  if ((layout.datatype == 16 || layout.datatype == 64) &&
      gzseek(f, static_cast<z_off_t>(layout.offset), SEEK_SET) >= 0) {
    if (layout.datatype == 16)
      for_each_value<float>(f, layout.swapped, count, restore);
    else
      for_each_value<double>(f, layout.swapped, count, restore);
  }
  gzclose(f);
  return restored;
}

void check_image_complete(const fs::path& file, std::uint64_t image_bytes) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  const bool meta = ext == ".mha" || ext == ".mhd", nifti = ext == ".nii" || ext == ".gz";
  if (!meta && !nifti)
    return;
  const auto [present, needed] =
      meta ? meta_bytes(file, image_bytes) : nifti_bytes(file, image_bytes);
  if (present < needed)
    input_error("'{}': cut short: {} bytes where its header announces {} (a truncated copy?)",
                file.string(), present, needed);
}

} // namespace tearflow
