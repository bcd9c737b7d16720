#include "bc/waveform.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <tuple>
#include <utility>

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/digest.hpp"
#include "core/error.hpp"

namespace tearflow::bc {
namespace {

/// 8-point Gauss-Legendre rule on [-1, 1] (exact for degree 15): nodes +-x_k, weights w_k.
constexpr std::array<double, 4> kGaussX{0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                        0.9602898564975363};
constexpr std::array<double, 4> kGaussW{0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                        0.1012285362903763};

double tolerance(double scale) {
  return 1e-9 * std::max(std::abs(scale), 1e-300);
}

/// The spline piece of interval i in the local variable s = t - t_i, s in [0, h]:
/// v = a + b s + c s^2 + d s^3 with a = v_i, b = (v_{i+1} - v_i)/h - h (2 M_i + M_{i+1})/6,
/// c = M_i / 2, d = (M_{i+1} - M_i) / (6 h).
struct Piece {
  double a, b, c, d, h;
  double value(double s) const { return a + s * (b + s * (c + s * d)); }
  double slope(double s) const { return b + s * (2.0 * c + 3.0 * s * d); }
};

Piece piece(const std::vector<double>& t, const std::vector<double>& v,
            const std::vector<double>& m, double period, size_t i) {
  const size_t ip = (i + 1) % t.size();
  const double h = (ip == 0 ? t[0] + period : t[ip]) - t[i];
  return {v[i], (v[ip] - v[i]) / h - h * (2.0 * m[i] + m[ip]) / 6.0, 0.5 * m[i],
          (m[ip] - m[i]) / (6.0 * h), h};
}

/// The piece containing t and the local s, with t mapped into [t_0, t_0 + T) for any sign
/// of t - t_0 (periodic repetition).
std::pair<Piece, double> locate(const std::vector<double>& t, const std::vector<double>& v,
                                const std::vector<double>& m, double period, double time) {
  double tau = std::fmod(time - t[0], period);
  if (tau < 0.0)
    tau += period;
  if (tau >= period)
    tau = 0.0; // rounding of tau + period
  const size_t i = std::upper_bound(t.begin(), t.end(), t[0] + tau) - t.begin() - 1;
  const Piece p = piece(t, v, m, period, i);
  return {p, std::clamp(tau - (t[i] - t[0]), 0.0, p.h)};
}
} // namespace

Waveform Waveform::constant(double value) {
  Waveform w;
  w.constant_ = value;
  return w;
}

Waveform Waveform::periodic(std::vector<double> t, std::vector<double> v, double period,
                            const std::string& where) {
  if (t.size() != v.size())
    input_error("{}: {} sample times but {} values", where, t.size(), v.size());
  for (size_t i = 0; i < t.size(); ++i)
    if (!std::isfinite(t[i]) || !std::isfinite(v[i])) // also catches NaN
      input_error("{}: sample {} (t = {}, value = {}) is not a finite number", where, i + 1, t[i],
                  v[i]);
  if (!std::isfinite(period))
    input_error("{}: the period {} is not finite", where, period);
  for (size_t i = 1; i < t.size(); ++i)
    if (!(t[i] > t[i - 1]))
      input_error("{}: sample times must increase strictly, but sample {} has t = {} after "
                  "t = {}",
                  where, i + 1, t[i], t[i - 1]);
  if (t.size() < 3)
    input_error("{}: {} samples; a periodic waveform needs at least 3", where, t.size());
  const double span = t.back() - t.front();
  if (std::abs(span - period) <= tolerance(period)) {
    // The last sample closes the period: it must repeat the first (1% of the range allowed).
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    if (std::abs(v.back() - v.front()) > 1e-2 * (*hi - *lo))
      input_error("{}: the last sample (t = {}) closes the period but its value {} differs "
                  "from the first value {}",
                  where, t.back(), v.back(), v.front());
    t.pop_back();
    v.pop_back();
    if (t.size() < 3)
      input_error("{}: {} samples besides the one closing the period; a periodic waveform "
                  "needs at least 3",
                  where, t.size());
  } else if (!(period > span)) {
    input_error("{}: the period {} must exceed the sampled span {} (from t = {} to t = {}) "
                "unless the last sample closes it",
                where, period, span, t.front(), t.back());
  }

  // C2 periodic cubic spline: with h_i = t_{i+1} - t_i (t_n = t_0 + T, indices mod n) the
  // second derivatives M_i solve the cyclic tridiagonal system
  //   h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1}
  //     = 6 [ (v_{i+1} - v_i) / h_i - (v_i - v_{i-1}) / h_{i-1} ]   (strictly diag. dominant).
  const int n = static_cast<int>(t.size());
  std::vector<double> h(n);
  for (int i = 0; i < n; ++i)
    h[i] = (i + 1 < n ? t[i + 1] : t[0] + period) - t[i];
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) {
    const int im = (i + n - 1) % n, ip = (i + 1) % n;
    entries.emplace_back(i, im, h[im]);
    entries.emplace_back(i, i, 2.0 * (h[im] + h[i]));
    entries.emplace_back(i, ip, h[i]);
    rhs[i] = 6.0 * ((v[ip] - v[i]) / h[i] - (v[i] - v[im]) / h[im]);
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(A);
  const Eigen::VectorXd m = lu.solve(rhs);

  Waveform w;
  w.t_ = std::move(t);
  w.v_ = std::move(v);
  w.m_.assign(m.data(), m.data() + n);
  w.period_ = period;
  w.check_overshoot(where);
  return w;
}

Waveform::Overshoot Waveform::overshoot() const {
  Overshoot o;
  if (is_constant())
    return o;
  const auto [lo, hi] = std::minmax_element(v_.begin(), v_.end());
  o.low = *lo;
  o.high = *hi;
  double below = 0.0, above = 0.0;
  for (size_t i = 0; i < t_.size(); ++i) { // sampled between the knots
    const double next = i + 1 < t_.size() ? t_[i + 1] : t_.front() + period_;
    for (int k = 1; k < 16; ++k) {
      const double t = t_[i] + (next - t_[i]) * k / 16.0, v = (*this)(t);
      if (*lo - v > std::max(below, above))
        std::tie(below, o.time, o.value) = std::tuple{*lo - v, t, v};
      if (v - *hi > std::max(below, above))
        std::tie(above, o.time, o.value) = std::tuple{v - *hi, t, v};
    }
  }
  o.fraction = *hi > *lo ? std::max(below, above) / (*hi - *lo) : 0.0;
  return o;
}

void Waveform::check_overshoot(const std::string& where) const {
  // A spline through a jump or a spike between coarse samples swings far beyond them (the
  // probe's spike gave a periodic 0D start pressure of -56,663 mmHg without a word): beyond
  // 10 % of the samples' range is said (the study's inflow closing its valve: 5.9 %,
  // tests/test_waveform.cpp). A warning, not an error: a coarse waveform may be meant.
  const Overshoot o = overshoot();
  if (o.fraction > 0.1)
    spdlog::warn("{}: the smooth interpolation (periodic cubic spline) through the samples "
                 "reaches {:.4g} at t = {:.4g} s, beyond their range {:.4g} to {:.4g} by {:.0f} % "
                 "of it (a jump or a spike between coarse samples?); sample the waveform more "
                 "finely there if that is not meant",
                 where, o.value, o.time, o.low, o.high, 100.0 * o.fraction);
}

double Waveform::operator()(double t) const {
  if (is_constant())
    return constant_;
  const auto [p, s] = locate(t_, v_, m_, period_, t);
  return p.value(s);
}

double Waveform::derivative(double t) const {
  if (is_constant())
    return 0.0;
  const auto [p, s] = locate(t_, v_, m_, period_, t);
  return p.slope(s);
}

double Waveform::mean() const {
  if (is_constant())
    return constant_;
  // int_0^h of the piece = h (v_i + v_{i+1}) / 2 - h^3 (M_i + M_{i+1}) / 24.
  double sum = 0.0;
  for (size_t i = 0; i < t_.size(); ++i) {
    const size_t ip = (i + 1) % t_.size();
    const double h = piece(t_, v_, m_, period_, i).h;
    sum += 0.5 * h * (v_[i] + v_[ip]) - h * h * h * (m_[i] + m_[ip]) / 24.0;
  }
  return sum / period_;
}

std::vector<std::complex<double>> Waveform::fourier(int modes) const {
  std::vector<std::complex<double>> c(std::max(modes, 0));
  if (c.empty())
    return c;
  c[0] = mean();
  if (is_constant())
    return c;
  // c_n = (1/T) int v(t) exp(-i n w t) dt, piece by piece with 8-point Gauss rules on
  // sub-intervals of length <= 1 / (n w): the integrand (cubic times exponential) is then
  // integrated to rounding error (the rule's error term scales with (n w h_sub)^16 / 16!).
  const double w = 2.0 * std::numbers::pi / period_;
  for (int n = 1; n < modes; ++n) {
    const double lambda = n * w;
    std::complex<double> sum = 0.0;
    for (size_t i = 0; i < t_.size(); ++i) {
      const Piece p = piece(t_, v_, m_, period_, i);
      const int sub = std::max(1, static_cast<int>(std::ceil(lambda * p.h)));
      const double hs = p.h / sub;
      for (int k = 0; k < sub; ++k)
        for (int q = 0; q < 8; ++q) {
          const double s = (k + 0.5 + 0.5 * (q < 4 ? -kGaussX[q] : kGaussX[q - 4])) * hs;
          sum += 0.5 * hs * kGaussW[q % 4] * p.value(s) * std::polar(1.0, -lambda * (t_[i] + s));
        }
    }
    c[n] = sum / period_;
  }
  return c;
}

Waveform Waveform::scaled(double s) const {
  Waveform w = *this;
  w.constant_ *= s;
  for (double& x : w.v_)
    x *= s;
  for (double& x : w.m_)
    x *= s;
  return w;
}

// ---------------------------------------------------------------------------- file readers
namespace {

struct Sample {
  double t, v;
  int line;
};

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos)
    return {};
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

/// Fields of a line: comma separated when it has a comma, else whitespace separated.
std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  const bool comma = line.find(',') != std::string_view::npos;
  const char* sep = comma ? "," : " \t";
  size_t pos = 0;
  while (pos <= line.size()) {
    const size_t end = std::min(line.find_first_of(sep, pos), line.size());
    const std::string_view f = trim(line.substr(pos, end - pos));
    if (comma || !f.empty())
      out.push_back(f);
    pos = end + 1;
  }
  return out;
}

std::optional<double> number(std::string_view f) {
  if (!f.empty() && f.front() == '+')
    f.remove_prefix(1);
  double x;
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), x);
  if (ec != std::errc() || ptr != f.data() + f.size() || f.empty())
    return std::nullopt;
  return x;
}

/// Reads the content lines of a file (comments after '#' and blank lines skipped); calls
/// `on_line(fields, line_number)` for each.
template <typename F> void for_each_line(const std::filesystem::path& file, F&& on_line) {
  std::ifstream in(file);
  if (!in)
    input_error("{}: cannot open the waveform file", file.string());
  std::string text;
  for (int no = 1; std::getline(in, text); ++no) {
    std::string_view s = text;
    s = trim(s.substr(0, s.find('#')));
    if (!s.empty())
      on_line(fields(s), no);
  }
}

/// Parses "time, value" fields into a sample; errors name the file and line.
Sample parse_sample(const std::filesystem::path& file, const std::vector<std::string_view>& f,
                    int line) {
  if (f.size() != 2)
    input_error("{}:{}: {} fields; expected two columns (time, value)", file.string(), line,
                f.size());
  double x[2];
  for (int k = 0; k < 2; ++k) {
    const auto n = number(f[k]);
    if (!n)
      input_error("{}:{}: non-numeric field '{}'", file.string(), line, f[k]);
    if (!std::isfinite(*n))
      input_error("{}:{}: field '{}' is not finite", file.string(), line, f[k]);
    x[k] = *n;
  }
  return {x[0], x[1], line};
}

void check_monotone(const std::filesystem::path& file, const std::vector<Sample>& s) {
  for (size_t i = 1; i < s.size(); ++i)
    if (!(s[i].t > s[i - 1].t))
      input_error("{}:{}: time {} does not increase (the previous sample, line {}, has time {})",
                  file.string(), s[i].line, s[i].t, s[i - 1].line, s[i - 1].t);
}

Waveform make(const std::filesystem::path& file, const std::vector<Sample>& s, double period) {
  if (s.size() < 3)
    input_error("{}: {} samples; a periodic waveform needs at least 3", file.string(), s.size());
  std::vector<double> t, v;
  for (const Sample& x : s) {
    t.push_back(x.t);
    v.push_back(x.v);
  }
  if (period <= 0.0)
    period = t.back() - t.front(); // the last sample closes the period
  for (const Sample& x : s)
    if (x.t - s.front().t > period + tolerance(period))
      input_error("{}:{}: time {} s lies beyond one period ({} s after the first sample)",
                  file.string(), x.line, x.t, period);
  return Waveform::periodic(std::move(t), std::move(v), period, file.string());
}

} // namespace

Waveform read_waveform_csv(const std::filesystem::path& file, double time_scale, double value_scale,
                           double period) {
  std::vector<Sample> s;
  bool first = true;
  for_each_line(file, [&](const std::vector<std::string_view>& f, int line) {
    // A first line with a non-numeric field is a header.
    const bool header =
        first && std::any_of(f.begin(), f.end(), [](std::string_view x) { return !number(x); });
    first = false;
    if (header)
      return;
    s.push_back(parse_sample(file, f, line));
  });
  check_monotone(file, s); // in the file's units, as the message quotes them
  for (Sample& x : s) {
    x.t *= time_scale;
    x.v *= value_scale;
  }
  return make(file, s, period);
}

Waveform read_simvascular_flow(const std::filesystem::path& file, double value_scale) {
  std::vector<Sample> s;
  long announced = -1;
  int header_line = 0;
  for_each_line(file, [&](const std::vector<std::string_view>& f, int line) {
    if (announced < 0) { // "nsamples nmodes"
      const auto n = f.empty() ? std::nullopt : number(f[0]);
      if (f.size() > 2 || !n || *n < 1 || *n != std::floor(*n) || (f.size() == 2 && !number(f[1])))
        input_error("{}:{}: expected the header 'nsamples nmodes'", file.string(), line);
      announced = static_cast<long>(*n);
      header_line = line;
      return;
    }
    Sample x = parse_sample(file, f, line);
    x.v *= value_scale;
    s.push_back(x);
  });
  if (announced < 0)
    input_error("{}: empty file; expected 'nsamples nmodes'", file.string());
  if (static_cast<long>(s.size()) != announced)
    input_error("{}:{}: the header announces {} samples but the file has {}", file.string(),
                header_line, announced, s.size());
  check_monotone(file, s);
  return make(file, s, 0.0); // the last sample is at t = period and repeats the first
}

std::string describe(const Waveform& w) {
  if (w.is_constant())
    return fmt::format("{}", w(0.0));
  std::vector<double> v;
  for (int k = 0; k < 97; ++k)
    v.push_back(w(w.period() * k / 97.0));
  return fmt::format("period {} s, digest {:016x}", w.period(),
                     fnv1a(v.data(), v.size() * sizeof(double)));
}

} // namespace tearflow::bc
