// The report's animated PNG: frames in one palette, each after the first stored as the
// rectangle that changed. An independent reader here composes the frames as a browser does
// (APNG: fcTL regions drawn over the canvas, dispose none, blend source) and compares them
// with the input pictures.
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <zlib.h>

#include "core/error.hpp"
#include "report/apng.hpp"
#include "report/palette.hpp"

namespace fs = std::filesystem;
using tearflow::report::Rgba;

namespace {

using Frame = std::vector<Rgba>; // rows from the top

std::uint32_t u32(const std::string& s, std::size_t at) {
  return (std::uint32_t(std::uint8_t(s[at])) << 24) |
         (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
         (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}

/// Writes an RGB picture (rows from the top) with VTK's writer, which filters rows as libpng
/// chooses (Sub, Up, Average, Paeth), so the frames' reader meets every filter.
void write_png(const Frame& f, int w, int h, const fs::path& file) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(w, h, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto* p = static_cast<unsigned char*>(image->GetScalarPointer(x, h - 1 - y, 0)); // VTK: y up
      const Rgba c = f[std::size_t(y) * w + x];
      p[0] = c >> 24;
      p[1] = (c >> 16) & 0xff;
      p[2] = (c >> 8) & 0xff;
    }
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(image);
  writer->SetFileName(file.string().c_str());
  writer->Write();
}

struct Animation {
  std::uint32_t width = 0, height = 0, frames_declared = 0;
  std::vector<Rgba> palette;
  std::vector<std::array<std::uint32_t, 4>> regions; // x, y, width, height
  std::vector<Frame> frames;                         // the canvas after each frame
};

/// Reads an 8-bit indexed APNG and composes its frames.
Animation read_apng(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(b.compare(0, 8, "\x89PNG\r\n\x1a\n"), 0);
  Animation a;
  Frame canvas;
  std::array<std::uint32_t, 4> region{};
  auto draw = [&](const std::string& deflated) {
    std::vector<std::uint8_t> raw(std::size_t(region[3]) * (region[2] + 1));
    uLongf size = raw.size();
    ASSERT_EQ(uncompress(raw.data(), &size, reinterpret_cast<const Bytef*>(deflated.data()),
                         deflated.size()),
              Z_OK);
    ASSERT_EQ(size, raw.size());
    for (std::uint32_t y = 0; y < region[3]; ++y) {
      ASSERT_EQ(raw[y * (region[2] + 1)], 0) << "row filter";
      for (std::uint32_t x = 0; x < region[2]; ++x) {
        const std::uint8_t i = raw[y * (region[2] + 1) + 1 + x];
        ASSERT_LT(i, a.palette.size());
        canvas[std::size_t(region[1] + y) * a.width + region[0] + x] = a.palette[i];
      }
    }
    a.frames.push_back(canvas);
  };
  for (std::size_t at = 8; at + 12 <= b.size();) {
    const std::uint32_t length = u32(b, at);
    const std::string type = b.substr(at + 4, 4), data = b.substr(at + 8, length);
    at += 12 + length;
    if (type == "IHDR") {
      a.width = u32(data, 0);
      a.height = u32(data, 4);
      EXPECT_EQ(data[8], 8);
      EXPECT_EQ(data[9], 3); // indexed
      canvas.assign(std::size_t(a.width) * a.height, 0);
    } else if (type == "acTL") {
      a.frames_declared = u32(data, 0);
    } else if (type == "PLTE") {
      for (std::size_t k = 0; k + 2 < data.size(); k += 3)
        a.palette.push_back((Rgba(std::uint8_t(data[k])) << 24) |
                            (Rgba(std::uint8_t(data[k + 1])) << 16) |
                            (Rgba(std::uint8_t(data[k + 2])) << 8) | 0xff);
    } else if (type == "fcTL") {
      region = {u32(data, 12), u32(data, 16), u32(data, 4), u32(data, 8)};
      EXPECT_LE(region[0] + region[2], a.width);
      EXPECT_LE(region[1] + region[3], a.height);
      EXPECT_EQ(data[24], 0); // dispose: none
      EXPECT_EQ(data[25], 0); // blend: source
      a.regions.push_back(region);
    } else if (type == "IDAT") {
      draw(data);
    } else if (type == "fdAT") {
      draw(data.substr(4));
    }
  }
  return a;
}

struct Frames {
  int w = 0, h = 0;
  std::vector<Frame> pictures;
  std::vector<fs::path> files;
};

Frames make_frames(const fs::path& dir, int w, int h, int n,
                   const std::function<Rgba(int, int, int)>& colour) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  Frames f{w, h, {}, {}};
  for (int k = 0; k < n; ++k) {
    Frame p(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        p[std::size_t(y) * w + x] = colour(k, x, y);
    f.files.push_back(dir / ("frame_" + std::to_string(k) + ".png"));
    write_png(p, w, h, f.files.back());
    f.pictures.push_back(p);
  }
  return f;
}

Rgba rgb(int r, int g, int b) {
  return (Rgba(r) << 24) | (Rgba(g) << 16) | (Rgba(b) << 8) | 0xff;
}

} // namespace

TEST(Apng, FewColoursRoundTripExactlyAndOnlyChangedRegionsAreStored) {
  // A blocky background (150 colours) with a square that moves in frames 0-2; frame 3 equals
  // frame 2. At most 256 colours, so the palette is exact and every frame comes back as drawn.
  const int w = 60, h = 40;
  auto colour = [](int k, int x, int y) {
    const int square_x = 10 + 7 * std::min(k, 2);
    if (x >= square_x && x < square_x + 8 && y >= 12 && y < 20)
      return rgb(230, 20, 20);
    return rgb(x / 4 * 16, y / 4 * 20, 120); // 15 x 10 blocks: 150 colours
  };
  const Frames f = make_frames(fs::temp_directory_path() / "tearflow-apng-few", w, h, 4, colour);
  const fs::path out = f.files[0].parent_path() / "animation.png";
  tearflow::report::write_apng(f.files, 100, out);
  const Animation a = read_apng(out);
  ASSERT_EQ(a.width, std::uint32_t(w));
  ASSERT_EQ(a.height, std::uint32_t(h));
  EXPECT_EQ(a.frames_declared, 4u);
  ASSERT_EQ(a.frames.size(), 4u);
  for (int k = 0; k < 4; ++k)
    EXPECT_EQ(a.frames[k], f.pictures[k]) << "frame " << k;
  // Frame 1: the square moved from x 10-17 to 17-24, rows 12-19; frame 3: nothing changed.
  EXPECT_EQ(a.regions[0], (std::array<std::uint32_t, 4>{0, 0, 60, 40}));
  EXPECT_EQ(a.regions[1], (std::array<std::uint32_t, 4>{10, 12, 15, 8}));
  EXPECT_EQ(a.regions[3], (std::array<std::uint32_t, 4>{0, 0, 1, 1}));
}

TEST(Apng, ManyColoursMapToTheNearestOfAMedianCutPalette) {
  // A 16^3 lattice of colours (step 17, 4096 colours, each on 4 pixels): median cut gives 256
  // boxes of 16 lattice points, 2 x 2 x 4 when the splits alternate; a pixel's error is then at
  // most 1.5 steps in one channel and 0.5 in the others, rms over the channels 0.76 steps =
  // 13 levels. Held to one step, 17 levels, and every pixel to its nearest palette entry.
  const int w = 128, h = 128;
  auto colour = [](int, int x, int y) {
    const int i = (y / 2) * 64 + x / 2; // 0..4095
    return rgb(17 * (i % 16), 17 * (i / 16 % 16), 17 * (i / 256));
  };
  const Frames f = make_frames(fs::temp_directory_path() / "tearflow-apng-many", w, h, 1, colour);
  const fs::path out = f.files[0].parent_path() / "animation.png";
  tearflow::report::write_apng(f.files, 100, out);
  const Animation a = read_apng(out);
  ASSERT_EQ(a.frames.size(), 1u);
  EXPECT_EQ(a.palette.size(), 256u);
  auto channel = [](Rgba c, int k) { return int(c >> (24 - 8 * k) & 0xff); };
  auto distance2 = [&](Rgba p, Rgba q) {
    int d = 0;
    for (int k = 0; k < 3; ++k)
      d += (channel(p, k) - channel(q, k)) * (channel(p, k) - channel(q, k));
    return d;
  };
  double sum2 = 0;
  for (std::size_t i = 0; i < f.pictures[0].size(); ++i) {
    const Rgba want = f.pictures[0][i], got = a.frames[0][i];
    int nearest = 1 << 30;
    for (const Rgba p : a.palette)
      nearest = std::min(nearest, distance2(want, p));
    ASSERT_EQ(distance2(want, got), nearest) << "pixel " << i;
    sum2 += distance2(want, got);
  }
  EXPECT_LE(std::sqrt(sum2 / (3.0 * f.pictures[0].size())), 17.0);
}

TEST(Apng, BadFramesAreNamed) {
  const fs::path dir = fs::temp_directory_path() / "tearflow-apng-bad";
  const Frames f = make_frames(dir, 8, 8, 1, [](int, int x, int) { return rgb(x, 0, 0); });
  const Frames g = make_frames(dir / "other", 9, 8, 1, [](int, int, int) { return rgb(0, 0, 0); });
  auto fails_with = [&](const std::vector<fs::path>& frames, const std::string& expected) {
    try {
      tearflow::report::write_apng(frames, 100, dir / "out.png");
      ADD_FAILURE() << "no error; expected: " << expected;
    } catch (const tearflow::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  fails_with({f.files[0], g.files[0]}, "'" + g.files[0].string() + "' differs in size");
  std::ofstream(dir / "text.png") << "not a picture";
  fails_with({dir / "text.png"}, "'" + (dir / "text.png").string() + "' is not a PNG file");
  // Cut short inside its image data: the bytes up to the middle of the file.
  std::ifstream in(f.files[0], std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(dir / "short.png", std::ios::binary) << bytes.substr(0, bytes.size() - 20);
  fails_with({dir / "short.png"}, (dir / "short.png").string());
  EXPECT_FALSE(fs::exists(dir / "out.png"));
}
