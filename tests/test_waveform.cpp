// Periodic waveforms: the C2 periodic cubic spline, its mean and Fourier coefficients, and
// the CSV and SimVascular .flow readers.
#include <cmath>
#include <fstream>
#include <numbers>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bc/waveform.hpp"
#include "core/error.hpp"

using namespace tearflow;
using bc::Waveform;

namespace {

constexpr double kPi = std::numbers::pi;

/// f(t) = sin(w t) + cos(3 w t), T = 1; f'''' = w^4 (sin(w t) + 81 cos(3 w t)), |f''''| <= 82 w^4.
constexpr double kW = 2.0 * kPi;
double f(double t) {
  return std::sin(kW * t) + std::cos(3.0 * kW * t);
}
double df(double t) {
  return kW * (std::cos(kW * t) - 3.0 * std::sin(3.0 * kW * t));
}

Waveform sampled(int n, double (*g)(double)) {
  std::vector<double> t, v;
  for (int i = 0; i < n; ++i) {
    t.push_back(double(i) / n);
    v.push_back(g(t.back()));
  }
  return Waveform::periodic(t, v, 1.0, "test");
}

/// Max errors of the spline and its derivative against f, f' on a fine grid.
std::pair<double, double> max_errors(const Waveform& w) {
  double e = 0.0, ed = 0.0;
  for (int k = 0; k <= 10000; ++k) {
    const double t = k / 10000.0;
    e = std::max(e, std::abs(w(t) - f(t)));
    ed = std::max(ed, std::abs(w.derivative(t) - df(t)));
  }
  return {e, ed};
}

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "tearflow_waveform_" + name;
  std::ofstream(path) << text;
  return path;
}

/// Runs `read` and returns the InputError message ("" when nothing is thrown).
template <typename F> std::string error_of(F&& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(Waveform, ReproducesSamples) {
  const std::vector<double> t{0.1, 0.17, 0.4, 0.45, 0.8, 0.93}, v{3.0, -1.0, 2.5, 2.0, 7.0, 0.5};
  const Waveform w = Waveform::periodic(t, v, 1.0, "test");
  EXPECT_DOUBLE_EQ(w.period(), 1.0);
  EXPECT_FALSE(w.is_constant());
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR(w(t[i]), v[i], 1e-14) << i;
    EXPECT_NEAR(w(t[i] + 3.0), v[i], 1e-13) << i;
  }
  // The spline is C1 across the wrap (t_last -> t_first + T) and at knots.
  for (double tk : {0.1, 0.4, 1.1}) {
    EXPECT_NEAR(w.derivative(tk - 1e-9), w.derivative(tk + 1e-9), 1e-5) << tk;
    EXPECT_NEAR(w(tk - 1e-9), w(tk + 1e-9), 1e-6) << tk;
  }
}

TEST(Waveform, SmoothFunctionAccuracy) {
  // Hall & Meyer (1976): a C2 periodic cubic spline interpolant of f has
  //   |f - s| <= 5/384 h^4 |f''''|,  |f' - s'| <= 1/24 h^3 |f''''|.
  // With h = 1/32 and |f''''| <= 82 (2 pi)^4: 1.6e-3 and 0.16 (|f'| reaches 8 pi).
  const double h = 1.0 / 32.0, f4 = 82.0 * std::pow(kW, 4);
  const auto [e32, ed32] = max_errors(sampled(32, f));
  EXPECT_LT(e32, 5.0 / 384.0 * std::pow(h, 4) * f4);
  EXPECT_LT(ed32, 1.0 / 24.0 * std::pow(h, 3) * f4);
  // And the orders: halving h divides the errors by about 16 and 8.
  const auto [e64, ed64] = max_errors(sampled(64, f));
  EXPECT_GT(e32 / e64, 14.0);
  EXPECT_GT(ed32 / ed64, 7.0);
  std::printf("N=32: |f-s| = %.3g, |f'-s'| = %.3g; N=64: %.3g, %.3g\n", e32, ed32, e64, ed64);
}

TEST(Waveform, MeanIsExactIntegral) {
  // Simpson's rule is exact on each cubic piece.
  const std::vector<double> t{0.0, 0.1, 0.35, 0.5, 0.9, 1.4}, v{1.0, 4.0, -2.0, 0.5, 3.0, 2.0};
  const double T = 2.0;
  const Waveform w = Waveform::periodic(t, v, T, "test");
  double integral = 0.0;
  for (size_t i = 0; i < t.size(); ++i) {
    const double a = t[i], b = i + 1 < t.size() ? t[i + 1] : t[0] + T;
    integral += (b - a) / 6.0 * (w(a) + 4.0 * w(0.5 * (a + b)) + w(b));
  }
  EXPECT_NEAR(w.mean(), integral / T, 1e-14);
  // On uniform knots the periodic spline's mean is the samples' average (sum M_i = 0).
  EXPECT_NEAR(sampled(32, [](double x) { return 2.0 + f(x); }).mean(), 2.0, 1e-14);
  EXPECT_NEAR(w.scaled(-3.0).mean(), -3.0 * w.mean(), 1e-14);
}

TEST(Waveform, FourierOfPureHarmonic) {
  // v = A cos(3 w t + phi) on 32 uniform samples: the spline's c_3 is (A/2) e^{i phi} times the
  // cubic-spline attenuation sigma = sinc^4(theta/2) 3 / (2 + cos theta), theta = 3 w h
  // (sigma = 0.99985); its aliases are at n = 29, 35, ..., so c_n = 0 for other n < 29.
  const double A = 2.5, phi = 0.7, h = 1.0 / 32.0, theta = 3.0 * kW * h;
  std::vector<double> t, v;
  for (int i = 0; i < 32; ++i) {
    t.push_back(i * h);
    v.push_back(A * std::cos(3.0 * kW * t.back() + phi));
  }
  const Waveform w = Waveform::periodic(t, v, 1.0, "test");
  const auto c = w.fourier(20);
  ASSERT_EQ(c.size(), 20u);
  const double sinc = std::sin(theta / 2) / (theta / 2);
  const double sigma = std::pow(sinc, 4) * 3.0 / (2.0 + std::cos(theta));
  EXPECT_LT(std::abs(c[3] - std::polar(0.5 * A * sigma, phi)), 1e-13);
  EXPECT_LT(std::abs(c[3] - std::polar(0.5 * A, phi)), 2e-4 * A); // sampled harmonic matches
  for (int n = 0; n < 20; ++n)
    if (n != 3) {
      EXPECT_LT(std::abs(c[n]), 1e-14) << n;
    }
}

TEST(Waveform, FourierMatchesQuadrature) {
  // Non-uniform knots, period 2, first knot not at 0: compare with the trapezoidal rule on
  // 2^15 points (error O(M^-4) from the jumps of the spline's third derivative: ~1e-15).
  const std::vector<double> t{0.3, 0.5, 0.9, 1.0, 1.6, 1.9}, v{1.0, 4.0, -2.0, 0.5, 3.0, 2.0};
  const double T = 2.0, w = 2.0 * kPi / T;
  const Waveform s = Waveform::periodic(t, v, T, "test");
  const auto c = s.fourier(12);
  const int M = 1 << 15;
  for (int n = 0; n < 12; ++n) {
    std::complex<double> sum = 0.0;
    for (int k = 0; k < M; ++k)
      sum += s(k * T / M) * std::polar(1.0, -n * w * k * T / M);
    EXPECT_LT(std::abs(c[n] - sum / double(M)), 1e-12) << n;
  }
  // The real series v = Re(c_0 + 2 sum c_n e^{i n w t}) converges to the spline (slowly:
  // its coefficients decay like n^-4).
  const auto c400 = s.fourier(400);
  for (double x : {0.0, 0.77, 1.55}) {
    double sum = c400[0].real();
    for (int n = 1; n < 400; ++n)
      sum += 2.0 * (c400[n] * std::polar(1.0, n * w * x)).real();
    EXPECT_NEAR(sum, s(x), 1e-6) << x;
  }
}

TEST(Waveform, PeriodicWrap) {
  const std::vector<double> t{0.2, 0.5, 0.9, 1.1}, v{1.0, 3.0, -1.0, 0.0};
  const Waveform w = Waveform::periodic(t, v, 1.2, "test"); // spans [0.2, 1.4)
  for (double x : {0.2, 0.33, 0.95, 1.3})
    for (int k : {-5, -1, 1, 4}) {
      EXPECT_NEAR(w(x + k * 1.2), w(x), 1e-12) << x << " " << k;
      EXPECT_NEAR(w.derivative(x + k * 1.2), w.derivative(x), 1e-10) << x << " " << k;
    }
  EXPECT_NEAR(w(-1.0), 1.0, 1e-12); // -1.0 = 0.2 - 1.2
  EXPECT_NEAR(w(0.0), w(1.2), 1e-12);
}

TEST(Waveform, ConstantAndScaled) {
  const Waveform c = Waveform::constant(4.0);
  EXPECT_TRUE(c.is_constant());
  EXPECT_EQ(c.period(), 0.0);
  EXPECT_EQ(c(-7.0), 4.0);
  EXPECT_EQ(c.derivative(1.0), 0.0);
  EXPECT_EQ(c.mean(), 4.0);
  const auto cf = c.fourier(3);
  EXPECT_EQ(cf[0], std::complex<double>(4.0));
  EXPECT_EQ(cf[2], std::complex<double>(0.0));
  EXPECT_EQ(c.scaled(-0.5)(3.0), -2.0);
  const Waveform s = sampled(32, f), m = s.scaled(-2.0);
  for (double x : {0.05, 0.6}) {
    EXPECT_NEAR(m(x), -2.0 * s(x), 1e-14);
    EXPECT_NEAR(m.derivative(x), -2.0 * s.derivative(x), 1e-12);
  }
}

TEST(Waveform, PeriodicInputErrors) {
  auto err = [](std::vector<double> t, std::vector<double> v, double T) {
    return error_of([&] { Waveform::periodic(t, v, T, "case.yaml:12"); });
  };
  EXPECT_NE(err({0, 1, 1, 2}, {1, 2, 3, 4}, 3).find("case.yaml:12"), std::string::npos);
  EXPECT_NE(err({0, 2, 1}, {1, 2, 3}, 3).find("increase"), std::string::npos);
  EXPECT_NE(err({0, 1}, {1, 2}, 3).find("at least 3"), std::string::npos);
  EXPECT_NE(err({0, 1, 2}, {1, 2, 1}, 2).find("at least 3"), std::string::npos); // 2 after closing
  EXPECT_NE(err({0, 1, 2, 3}, {1, 2, 3, 4}, 2.5).find("period"), std::string::npos);
  EXPECT_NE(err({0, 1, 2}, {1, NAN, 3}, 5).find("finite"), std::string::npos);
  EXPECT_NE(err({0, 1, 2, 3}, {1, 2, 3, 9}, 3).find("closes the period"), std::string::npos);
  EXPECT_EQ(err({0, 1, 2, 3}, {1, 2, 3, 1}, 3), ""); // closing sample repeats the first
}

TEST(Waveform, ReadsSimVascularFlow) {
  const std::string path = TEARFLOW_SHARED_DIR "/meshes/pipe-rcr/inflow.flow";
  const Waveform w = bc::read_simvascular_flow(path, 1.0);
  EXPECT_DOUBLE_EQ(w.period(), 1.0);
  // Compare with the file itself: 33 lines, the last (t = 1) repeats the first.
  std::ifstream in(path);
  int n, modes;
  in >> n >> modes;
  std::vector<double> t(n), v(n);
  for (int i = 0; i < n; ++i)
    in >> t[i] >> v[i];
  ASSERT_TRUE(in || in.eof());
  ASSERT_EQ(n, 33);
  EXPECT_EQ(t.back(), 1.0);
  EXPECT_EQ(v.back(), v.front());
  for (int i = 0; i + 1 < n; ++i) { // 32 distinct samples, reproduced with the file's sign
    if (i > 0) {
      EXPECT_GT(t[i], t[i - 1]);
    }
    EXPECT_NEAR(w(t[i]), v[i], 1e-12) << i;
  }
  // The file samples -20 pi (1 - cos 2 pi t): mean -20 pi, c_1 = 10 pi.
  EXPECT_NEAR(w.mean(), -20.0 * kPi, 1e-5);
  EXPECT_NEAR(w.fourier(2)[1].real(), 10.0 * kPi, 1e-3); // spline attenuation 2e-6
  EXPECT_NEAR(bc::read_simvascular_flow(path, 1e-6).mean(), -20e-6 * kPi, 1e-11);
}

TEST(Waveform, SimVascularCountMismatch) {
  const auto path = write_file("bad.flow", "4 2\n0 1\n0.5 2\n1 1\n");
  const std::string e = error_of([&] { bc::read_simvascular_flow(path, 1.0); });
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("announces 4"), std::string::npos) << e;
}

TEST(Waveform, CsvWithHeaderCommentsAndUnits) {
  const auto path = write_file("ok.csv", "time [ms], flow [ml/s]  # header\n"
                                         "# a comment line\n"
                                         "0, 1\n"
                                         "\n"
                                         "250 ,2\n"
                                         "  500,\t3   # inline comment\r\n"
                                         "750 , 2\n"
                                         "1000,1\n");
  const Waveform w = bc::read_waveform_csv(path, 1e-3, 1e-6, 0.0); // period from the last sample
  EXPECT_NEAR(w.period(), 1.0, 1e-15);
  EXPECT_NEAR(w(0.5), 3e-6, 1e-20);
  EXPECT_NEAR(w(0.25), 2e-6, 1e-20);
  EXPECT_NEAR(w(1.0), 1e-6, 1e-20);
  // With a given period (SI seconds) the last sample is kept.
  const Waveform p = bc::read_waveform_csv(path, 1e-3, 1.0, 1.25);
  EXPECT_DOUBLE_EQ(p.period(), 1.25);
  EXPECT_NEAR(p(1.0), 1.0, 1e-14);
}

TEST(Waveform, CsvErrorsNameFileAndLine) {
  const auto bad = write_file("nonmono.csv", "t,q\n0,1\n0.5,2\n0.4,3\n1,1\n");
  std::string e = error_of([&] { bc::read_waveform_csv(bad, 1.0, 1.0, 0.0); });
  EXPECT_NE(e.find(bad + ":4:"), std::string::npos) << e;
  const auto text = write_file("text.csv", "t,q\n0,1\n0.5,abc\n1,1\n");
  e = error_of([&] { bc::read_waveform_csv(text, 1.0, 1.0, 0.0); });
  EXPECT_NE(e.find(text + ":3:"), std::string::npos) << e;
  EXPECT_NE(e.find("abc"), std::string::npos) << e;
  const auto nan = write_file("nan.csv", "0,1\n0.5,nan\n1,1\n");
  e = error_of([&] { bc::read_waveform_csv(nan, 1.0, 1.0, 0.0); });
  EXPECT_NE(e.find(nan + ":2:"), std::string::npos) << e;
  const auto cols = write_file("cols.csv", "0,1,2\n");
  e = error_of([&] { bc::read_waveform_csv(cols, 1.0, 1.0, 0.0); });
  EXPECT_NE(e.find(cols + ":1:"), std::string::npos) << e;
  const auto beyond = write_file("beyond.csv", "0,1\n0.5,2\n0.7,2\n1.5,1\n");
  e = error_of([&] { bc::read_waveform_csv(beyond, 1.0, 1.0, 1.0); });
  EXPECT_NE(e.find(beyond + ":4:"), std::string::npos) << e;
  const auto few = write_file("few.csv", "# only two\n0,1\n1,1\n");
  e = error_of([&] { bc::read_waveform_csv(few, 1.0, 1.0, 0.0); });
  EXPECT_NE(e.find(few), std::string::npos) << e;
}

TEST(Waveform, MissingFile) {
  const std::string path = ::testing::TempDir() + "tearflow_no_such_waveform.csv";
  std::string e = error_of([&] { bc::read_waveform_csv(path, 1.0, 1.0, 0.0); });
  EXPECT_NE(e.find(path), std::string::npos) << e;
  e = error_of([&] { bc::read_simvascular_flow(path, 1.0); });
  EXPECT_NE(e.find(path), std::string::npos) << e;
}

TEST(Waveform, ASplineSwingingFarBeyondItsSamplesIsFound) {
  // A 2 ms spike between samples 100 ms apart (the probe's inflow): the C2 spline rings
  // through the neighbouring intervals far below zero, which loading warns of, with where.
  const bc::Waveform spike = bc::Waveform::periodic(
      {0.0, 0.1, 0.2, 0.201, 0.202, 0.3, 0.6}, {0, 0, 0, 400, 0, 0, 0}, 1.0, "spike.csv");
  const bc::Waveform::Overshoot o = spike.overshoot();
  EXPECT_GT(o.fraction, 0.5);
  EXPECT_TRUE(o.value < -200.0 || o.value > 600.0) << o.value; // beyond [0, 400] by half
  EXPECT_NEAR(spike(o.time), o.value, 1e-12);
  // The same spike sampled finely enough stays within its samples (a Gaussian: none).
  std::vector<double> t, v;
  for (int k = 0; k < 100; ++k) {
    t.push_back(0.01 * k);
    v.push_back(400.0 * std::exp(-std::pow((0.01 * k - 0.2) / 0.03, 2)));
  }
  EXPECT_LT(bc::Waveform::periodic(t, v, 1.0, "smooth.csv").overshoot().fraction, 0.1);
}

TEST(Waveform, TheStudysInflowStaysWithinItsSamples) {
  // examples/tbad-study's inflow (mL/s), its valve closing at 0.388 s: the spline's swing
  // beyond the samples, which the overshoot check allows up to 10 % of their range silently.
  const std::vector<double> t = {0.0,   0.02,  0.04,  0.06,  0.08,  0.1,   0.12,  0.14,  0.16,
                                 0.18,  0.2,   0.22,  0.24,  0.26,  0.28,  0.3,   0.32,  0.34,
                                 0.36,  0.38,  0.388, 0.438, 0.488, 0.538, 0.588, 0.638, 0.688,
                                 0.738, 0.788, 0.838, 0.888, 0.938, 0.988};
  const std::vector<double> v = {0.0,    48.37,  95.48,  140.08, 181.02, 217.23, 247.75,
                                 271.78, 288.71, 298.08, 299.65, 293.37, 279.42, 258.16,
                                 230.14, 196.11, 156.93, 113.66, 67.4,   19.39,  0.0};
  std::vector<double> values = v;
  values.resize(t.size(), 0.0);
  const bc::Waveform w = bc::Waveform::periodic(t, values, 1.0, "inflow");
  const bc::Waveform::Overshoot o = w.overshoot();
  std::printf("swing beyond the samples: %.2f %% of their range (to %.2f at t = %.3f s)\n",
              100 * o.fraction, o.value, o.time);
  double swing = 0.0; // densely, against the check's 15 points per interval
  for (int k = 0; k < 100000; ++k)
    swing = std::max({swing, -w(k * 1e-5) / 299.65, (w(k * 1e-5) - 299.65) / 299.65});
  EXPECT_NEAR(o.fraction, swing, 0.01);
  EXPECT_LT(swing, 0.1);
}
