#include "report/apng.hpp"

#include <cstdint>
#include <fstream>
#include <string>

#include <zlib.h>

#include "core/error.hpp"
#include "io/durable_file.hpp"

namespace tearflow::report {

namespace {

constexpr char kSignature[] = "\x89PNG\r\n\x1a\n";

struct Chunk {
  std::string type, data;
};

std::uint32_t read_u32(const std::string& s, std::size_t at) {
  return (std::uint32_t(std::uint8_t(s[at])) << 24) |
         (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
         (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8)
    s.push_back(static_cast<char>((v >> shift) & 0xff));
}

void put_u16(std::string& s, std::uint16_t v) {
  s.push_back(static_cast<char>(v >> 8));
  s.push_back(static_cast<char>(v & 0xff));
}

/// The chunks of a PNG file; InputError when it is not one.
std::vector<Chunk> read_chunks(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.compare(0, 8, kSignature, 8) != 0)
    input_error("animation: '{}' is not a PNG file", file.string());
  std::vector<Chunk> chunks;
  for (std::size_t at = 8; at + 12 <= bytes.size();) {
    const std::uint32_t length = read_u32(bytes, at);
    if (at + 12 + length > bytes.size())
      input_error("animation: '{}' is cut short", file.string());
    chunks.push_back({bytes.substr(at + 4, 4), bytes.substr(at + 8, length)});
    at += 12 + length;
  }
  return chunks;
}

/// Appends a chunk with its length and CRC (over type and data, as PNG defines it).
void put_chunk(std::string& out, const std::string& type, const std::string& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  out += body;
  put_u32(out, static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(body.data()),
                                                static_cast<uInt>(body.size()))));
}

} // namespace

void write_apng(const std::vector<std::filesystem::path>& frames, int delay_ms,
                const std::filesystem::path& out) {
  if (frames.empty())
    input_error("animation '{}': no frames", out.string());
  std::string png(kSignature, 8), header;
  std::uint32_t sequence = 0; // fcTL and fdAT chunks share one running number
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::vector<Chunk> chunks = read_chunks(frames[i]);
    if (chunks.empty() || chunks.front().type != "IHDR" || chunks.front().data.size() != 13)
      input_error("animation: '{}' has no PNG header", frames[i].string());
    if (i == 0) {
      header = chunks.front().data;
      put_chunk(png, "IHDR", header);
      std::string control;
      put_u32(control, static_cast<std::uint32_t>(frames.size()));
      put_u32(control, 0); // loop for ever
      put_chunk(png, "acTL", control);
    } else if (chunks.front().data != header) {
      input_error("animation: '{}' differs in size or pixel format from '{}'", frames[i].string(),
                  frames[0].string());
    }
    std::string frame_control;
    put_u32(frame_control, sequence++);
    frame_control += header.substr(0, 8); // width and height, as the header's
    put_u32(frame_control, 0);            // x offset
    put_u32(frame_control, 0);            // y offset
    put_u16(frame_control, static_cast<std::uint16_t>(delay_ms));
    put_u16(frame_control, 1000);            // the delay in milliseconds
    frame_control += std::string("\0\0", 2); // dispose: none; blend: source
    put_chunk(png, "fcTL", frame_control);
    for (const Chunk& c : chunks) {
      if (c.type != "IDAT")
        continue;
      if (i == 0) { // the first frame is the default image: its data stays IDAT
        put_chunk(png, "IDAT", c.data);
      } else {
        std::string data;
        put_u32(data, sequence++);
        put_chunk(png, "fdAT", data + c.data);
      }
    }
  }
  put_chunk(png, "IEND", "");
  io::write_file_atomically(out, png);
}

} // namespace tearflow::report
