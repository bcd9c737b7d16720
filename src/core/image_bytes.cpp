// Image files cut short (core/image_bytes.hpp): the bytes present against the header's.
#include "core/image_bytes.hpp"

#include <algorithm>
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

} // namespace

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
