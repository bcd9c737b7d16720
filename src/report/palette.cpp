#include "report/palette.hpp"

#include <algorithm>
#include <limits>
#include <utility>

namespace tearflow::report {

namespace {

int channel(Rgba c, int k) {
  return static_cast<int>((c >> (24 - 8 * k)) & 0xff);
}

struct Box {
  std::vector<std::pair<Rgba, std::uint64_t>> colours;
  double error = 0; // the pixels' squared distance to their mean, over the channels
  int widest = 0;   // the channel whose variance is largest
  Rgba mean = 0;
};

/// The box's mean colour, its pixels' squared error about it and its widest channel.
void measure(Box& b) {
  std::array<double, 4> sum{}, sum2{};
  double n = 0;
  for (const auto& [c, count] : b.colours) {
    for (int k = 0; k < 4; ++k) {
      sum[k] += double(count) * channel(c, k);
      sum2[k] += double(count) * channel(c, k) * channel(c, k);
    }
    n += double(count);
  }
  b.error = 0;
  b.mean = 0;
  double widest = -1;
  for (int k = 0; k < 4; ++k) {
    const double variance = sum2[k] - sum[k] * sum[k] / n;
    b.error += variance;
    if (variance > widest) {
      widest = variance;
      b.widest = k;
    }
    b.mean |= static_cast<Rgba>(std::clamp(sum[k] / n + 0.5, 0.0, 255.0)) << (24 - 8 * k);
  }
}

/// Splits `b` at its widest channel's weighted median; the upper half is returned.
Box split(Box& b) {
  const int k = b.widest;
  std::sort(b.colours.begin(), b.colours.end(), [k](const auto& x, const auto& y) {
    return channel(x.first, k) < channel(y.first, k);
  });
  std::uint64_t total = 0, below = 0;
  for (const auto& c : b.colours)
    total += c.second;
  std::size_t cut = 1; // both halves keep at least one colour
  for (; cut + 1 < b.colours.size(); ++cut) {
    below += b.colours[cut - 1].second;
    if (2 * below >= total)
      break;
  }
  Box upper;
  upper.colours.assign(b.colours.begin() + static_cast<std::ptrdiff_t>(cut), b.colours.end());
  b.colours.resize(cut);
  measure(b);
  measure(upper);
  return upper;
}

int distance2(Rgba a, Rgba b) {
  int d = 0;
  for (int k = 0; k < 4; ++k)
    d += (channel(a, k) - channel(b, k)) * (channel(a, k) - channel(b, k));
  return d;
}

} // namespace

Palette median_cut(const ColourCounts& counts, std::size_t size) {
  Palette p;
  if (counts.size() <= size) {
    for (const auto& entry : counts) {
      p.of[entry.first] = static_cast<std::uint8_t>(p.colours.size());
      p.colours.push_back(entry.first);
    }
    return p;
  }
  std::vector<Box> boxes(1);
  boxes[0].colours.assign(counts.begin(), counts.end());
  measure(boxes[0]);
  while (boxes.size() < size) {
    // The box that loses most by being one colour, of those with two colours or more.
    auto worst = boxes.end();
    for (auto b = boxes.begin(); b != boxes.end(); ++b)
      if (b->colours.size() > 1 && (worst == boxes.end() || b->error > worst->error))
        worst = b;
    if (worst == boxes.end())
      break;
    Box upper = split(*worst);
    boxes.push_back(std::move(upper));
  }
  for (const Box& b : boxes)
    p.colours.push_back(b.mean);
  for (const auto& entry : counts) {
    int best = std::numeric_limits<int>::max();
    for (std::size_t i = 0; i < p.colours.size(); ++i) {
      const int d = distance2(entry.first, p.colours[i]);
      if (d < best) {
        best = d;
        p.of[entry.first] = static_cast<std::uint8_t>(i);
      }
    }
  }
  return p;
}

} // namespace tearflow::report
