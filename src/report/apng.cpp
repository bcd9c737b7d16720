#include "report/apng.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include <zlib.h>

#include "core/error.hpp"
#include "io/durable_file.hpp"
#include "report/palette.hpp"

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

/// A frame's pixels, rows from the top.
struct Picture {
  std::string header; // IHDR's data
  std::uint32_t width = 0, height = 0;
  std::vector<Rgba> pixels;
};

/// PNG's Paeth predictor (PNG specification, 9.4).
int paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/// Decodes an 8-bit RGB or RGBA PNG without interlacing (what the renderer writes): its IDAT
/// data inflated and each row's filter undone. InputError naming the file otherwise.
Picture decode(const std::filesystem::path& file) {
  const std::vector<Chunk> chunks = read_chunks(file);
  if (chunks.empty() || chunks.front().type != "IHDR" || chunks.front().data.size() != 13)
    input_error("animation: '{}' has no PNG header", file.string());
  Picture p;
  p.header = chunks.front().data;
  p.width = read_u32(p.header, 0);
  p.height = read_u32(p.header, 4);
  const int depth = std::uint8_t(p.header[8]), type = std::uint8_t(p.header[9]);
  if (depth != 8 || (type != 2 && type != 6) || p.header[12] != 0 || p.width == 0 ||
      p.height == 0 || p.width > (1u << 16) || p.height > (1u << 16))
    input_error("animation: '{}' is not an 8-bit RGB or RGBA PNG without interlacing",
                file.string());
  const std::size_t bpp = type == 6 ? 4 : 3, stride = p.width * bpp;
  std::string compressed;
  for (const Chunk& c : chunks)
    if (c.type == "IDAT")
      compressed += c.data;
  std::vector<std::uint8_t> raw(p.height * (stride + 1));
  uLongf size = static_cast<uLongf>(raw.size());
  if (uncompress(raw.data(), &size, reinterpret_cast<const Bytef*>(compressed.data()),
                 static_cast<uLong>(compressed.size())) != Z_OK ||
      size != raw.size())
    input_error("animation: '{}' has corrupt or missing image data", file.string());
  std::vector<std::uint8_t> row(stride), above(stride, 0);
  p.pixels.resize(std::size_t(p.width) * p.height);
  for (std::uint32_t y = 0; y < p.height; ++y) {
    const std::uint8_t* in = &raw[y * (stride + 1)];
    const int filter = in[0];
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= bpp ? row[i - bpp] : 0, b = above[i], c = i >= bpp ? above[i - bpp] : 0;
      const int predicted = filter == 0   ? 0
                            : filter == 1 ? a
                            : filter == 2 ? b
                            : filter == 3 ? (a + b) / 2
                            : filter == 4 ? paeth(a, b, c)
                                          : -1;
      if (predicted < 0)
        input_error("animation: '{}' row {}: unknown filter {}", file.string(), y, filter);
      row[i] = static_cast<std::uint8_t>(in[i + 1] + predicted);
    }
    for (std::uint32_t x = 0; x < p.width; ++x) {
      const std::uint8_t* q = &row[x * bpp];
      p.pixels[std::size_t(y) * p.width + x] =
          (Rgba(q[0]) << 24) | (Rgba(q[1]) << 16) | (Rgba(q[2]) << 8) | (bpp == 4 ? q[3] : 0xff);
    }
    std::swap(row, above);
  }
  return p;
}

/// The rectangle in which two frames' palette indices differ (x, y, width, height); a single
/// pixel when they do not differ at all (APNG's frames are at least one pixel).
std::array<std::uint32_t, 4> changed_region(const std::vector<std::uint8_t>& previous,
                                            const std::vector<std::uint8_t>& current,
                                            std::uint32_t width, std::uint32_t height) {
  std::uint32_t x0 = width, x1 = 0, y0 = height, y1 = 0;
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x)
      if (previous[std::size_t(y) * width + x] != current[std::size_t(y) * width + x]) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  if (x0 > x1)
    return {0, 0, 1, 1};
  return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

/// The rectangle's palette indices as PNG image data: each row unfiltered (filter 0, which
/// suits palette images, PNG specification 12.8), deflated at zlib's best compression.
std::string image_data(const std::vector<std::uint8_t>& index, std::uint32_t width,
                       const std::array<std::uint32_t, 4>& r) {
  std::vector<std::uint8_t> raw;
  raw.reserve(std::size_t(r[3]) * (r[2] + 1));
  for (std::uint32_t y = r[1]; y < r[1] + r[3]; ++y) {
    raw.push_back(0);
    const auto row = index.begin() + static_cast<std::ptrdiff_t>(std::size_t(y) * width + r[0]);
    raw.insert(raw.end(), row, row + r[2]);
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string out(size, '\0');
  compress2(reinterpret_cast<Bytef*>(out.data()), &size, raw.data(), static_cast<uLong>(raw.size()),
            Z_BEST_COMPRESSION);
  out.resize(size);
  return out;
}

} // namespace

void write_apng(const std::vector<std::filesystem::path>& frames, int delay_ms,
                const std::filesystem::path& out) {
  if (frames.empty())
    input_error("animation '{}': no frames", out.string());
  // Two passes, so that only two frames are held at a time: the colours of all frames, then
  // each frame in the shared palette, stored as the region that changed since the one before.
  ColourCounts counts;
  std::string header;
  for (const std::filesystem::path& f : frames) {
    const Picture p = decode(f);
    if (header.empty())
      header = p.header;
    else if (p.header != header)
      input_error("animation: '{}' differs in size or pixel format from '{}'", f.string(),
                  frames[0].string());
    for (const Rgba c : p.pixels)
      ++counts[c];
  }
  const Palette palette = median_cut(counts);
  const std::uint32_t width = read_u32(header, 0), height = read_u32(header, 4);

  std::string png(kSignature, 8), indexed_header = header.substr(0, 8);
  indexed_header += std::string("\x08\x03\0\0\0", 5); // 8 bits, indexed, no interlacing
  put_chunk(png, "IHDR", indexed_header);
  std::string control;
  put_u32(control, static_cast<std::uint32_t>(frames.size()));
  put_u32(control, 0); // loop for ever
  put_chunk(png, "acTL", control);
  std::string plte, trns;
  bool opaque = true;
  for (const Rgba c : palette.colours) {
    plte += {char(c >> 24), char(c >> 16), char(c >> 8)};
    trns += char(c & 0xff);
    opaque = opaque && (c & 0xff) == 0xff;
  }
  put_chunk(png, "PLTE", plte);
  if (!opaque)
    put_chunk(png, "tRNS", trns);

  std::uint32_t sequence = 0; // fcTL and fdAT chunks share one running number
  std::vector<std::uint8_t> previous, index(std::size_t(width) * height);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const Picture p = decode(frames[i]);
    for (std::size_t k = 0; k < index.size(); ++k)
      index[k] = palette.of.at(p.pixels[k]);
    // The first frame is the default image and covers the canvas; each later one is drawn
    // over the one before (dispose: none; blend: source).
    const std::array<std::uint32_t, 4> region =
        i == 0 ? std::array<std::uint32_t, 4>{0, 0, width, height}
               : changed_region(previous, index, width, height);
    std::string frame_control;
    put_u32(frame_control, sequence++);
    put_u32(frame_control, region[2]);
    put_u32(frame_control, region[3]);
    put_u32(frame_control, region[0]);
    put_u32(frame_control, region[1]);
    put_u16(frame_control, static_cast<std::uint16_t>(delay_ms));
    put_u16(frame_control, 1000);            // the delay in milliseconds
    frame_control += std::string("\0\0", 2); // dispose: none; blend: source
    put_chunk(png, "fcTL", frame_control);
    const std::string data = image_data(index, width, region);
    if (i == 0) {
      put_chunk(png, "IDAT", data);
    } else {
      std::string numbered;
      put_u32(numbered, sequence++);
      put_chunk(png, "fdAT", numbered + data);
    }
    previous.swap(index);
    index.resize(previous.size());
  }
  put_chunk(png, "IEND", "");
  io::write_file_atomically(out, png);
}

} // namespace tearflow::report
