// Values that are not numbers (NaN) in a scan (issue 62). A NIfTI series with NaN velocity in
// the lumen read the NaN as no velocity: every flow 0 mL/s with all of vz NaN, every flow
// halved with every other vz voxel NaN, 0 mL/s in the frames that held them, and mri.json
// recorded nothing. Each pattern is written here as NIfTI and as MetaImage and measured by
// `tearflow mri flow`: a NaN that a landmark's lumen section reads is refused, exit 2, naming
// the file, the component, the frame and the landmark; NaN elsewhere is reported (count,
// frames, voxels) in the output and in mri.json, and the flows are those of the clean scan.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "geometry/landmarks.hpp"
#include "mri/compare.hpp"
#include "mri/corrections.hpp"
#include "mri/image_io.hpp"
#include "mri/vessel_flow.hpp"
#include "mri_support.hpp"

using namespace tearflow;
using namespace tearflow::testing;
namespace fs = std::filesystem;

namespace {

// NIfTI (compressed) and MetaImage: the two volume formats' readers.
const char* const kFormats[] = {".nii.gz", ".mha"};

/// The axis-aligned test pipe (R 6 mm, 21 x 21 x 12 voxels of 1.5 mm, 20 frames), noise-free.
const mri::PipeScan& pipe() {
  static const mri::PipeScan s = test_pipe_scan();
  return s;
}

/// In-plane distance of voxel v from the pipe's axis, in voxels.
double radius_of(const mri::Flow4D& data, std::size_t v) {
  const auto ijk = data.grid.ijk(v);
  const Vec3 centre = data.grid.index(pipe().axis_point);
  return std::hypot(ijk[0] - centre[0], ijk[1] - centre[1]);
}

struct Measured {
  Result result;
  fs::path dir; ///< images/, landmarks.json, flow/
  std::string file(const std::string& image, const std::string& ext) const {
    return (dir / "images" / (image + ext)).string();
  }
};

/// The pipe with `spoil` applied, written as volumes `ext`, measured by `tearflow mri flow`
/// at its plane (with --venc, so that unwrapping runs over the NaN too).
Measured measure(const std::string& name, const std::string& ext,
                 const std::function<void(mri::Flow4D&)>& spoil) {
  Measured m;
  m.dir = fresh_dir("mri-nan-" + name + (ext == ".mha" ? "-mha" : "-nii"));
  mri::Flow4D data = mri::synthesize_pipe(pipe());
  spoil(data);
  mri::write_volumes(data, m.dir / "images", ext);
  geometry::write_landmarks(test_pipe_landmarks(pipe()), m.dir / "landmarks.json");
  m.result = run_tearflow("mri flow " + (m.dir / "images").string() + " --landmarks " +
                          (m.dir / "landmarks.json").string() + " --venc 1m/s -o " +
                          (m.dir / "flow").string());
  return m;
}

long count_matches(const std::string& text, const std::string& pattern) {
  const std::regex re(pattern);
  return std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator());
}

/// A refusal: exit 2, one error naming the landmark, the frame, the component and its file;
/// no tables written.
void expect_refused(const Measured& m, const std::string& ext, int frame) {
  const std::string& out = m.result.output;
  EXPECT_EQ(m.result.code, 2) << out;
  EXPECT_EQ(count_matches(out, "error:"), 1) << out;
  EXPECT_NE(out.find(fmt::format("error: landmark 'AAo', frame {} (t = ", frame)),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("that are not numbers (NaN or infinite), from vz ('" + m.file("vz", ext) +
                     "'); the flow would be wrong"),
            std::string::npos)
      << out;
  EXPECT_FALSE(fs::exists(m.dir / "flow" / "flow.csv")) << out;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), {}};
}

} // namespace

TEST(MriNonFinite, AllOfVzNotANumberIsRefused) {
  // Was: every flow 0 mL/s, exit 0.
  for (const std::string ext : kFormats) {
    const Measured m = measure("all-vz", ext, [](mri::Flow4D& d) {
      for (mri::Frame& f : d.frames)
        std::fill(f.velocity[2].begin(), f.velocity[2].end(), std::nanf(""));
    });
    expect_refused(m, ext, 0);
    // The reading's count comes first, once: every value of vz in every frame.
    const std::size_t all = pipe().grid.count() * 20;
    EXPECT_NE(m.result.output.find(fmt::format("vz ('{}'): {} value(s) of {} are not numbers",
                                               m.file("vz", ext), all, all)),
              std::string::npos)
        << m.result.output;
  }
  // On 2 ranks (`mri` runs on one, the other waits): the same refusal once, exit 2, no
  // MPI_ABORT banner (issue 62, part 3).
  const Measured m = measure("all-vz", ".mha", [](mri::Flow4D& d) {
    for (mri::Frame& f : d.frames)
      std::fill(f.velocity[2].begin(), f.velocity[2].end(), std::nanf(""));
  });
  const Result two = run_tearflow("mri flow " + (m.dir / "images").string() + " --landmarks " +
                                      (m.dir / "landmarks.json").string() + " --venc 1m/s -o " +
                                      (m.dir / "flow-2").string(),
                                  "mpirun -n 2");
  EXPECT_EQ(two.code, 2) << two.output;
  EXPECT_EQ(count_matches(two.output, "error:"), 1) << two.output;
  EXPECT_EQ(two.output.find("MPI_ABORT"), std::string::npos) << two.output;
}

TEST(MriNonFinite, EveryOtherVzVoxelNotANumberIsRefused) {
  // Was: every flow about halved, exit 0.
  for (const std::string ext : kFormats) {
    const Measured m = measure("other-vz", ext, [](mri::Flow4D& d) {
      for (mri::Frame& f : d.frames)
        for (std::size_t v = 0; v < f.velocity[2].size(); v += 2)
          f.velocity[2][v] = std::nanf("");
    });
    expect_refused(m, ext, 0);
  }
}

TEST(MriNonFinite, NotANumberInTheFirstFramesIsRefusedNamingTheFrame) {
  // Was: 0 mL/s in frames 0-2, the others right. NaN in the lumen (and a voxel beyond it) of
  // frames 0-2 only; unwrapping used to carry a NaN on into every later frame of its voxel.
  for (const std::string ext : kFormats) {
    const Measured m = measure("first-frames", ext, [](mri::Flow4D& d) {
      for (std::size_t f = 0; f < 3; ++f)
        for (std::size_t v = 0; v < d.grid.count(); ++v)
          if (radius_of(d, v) < 5.0)
            d.frames[f].velocity[2][v] = std::nanf("");
    });
    expect_refused(m, ext, 0);
    EXPECT_NE(m.result.output.find("in frame(s) 0-2, voxels i"), std::string::npos)
        << m.result.output;
  }
}

TEST(MriNonFinite, NotANumberOutsideTheLumenIsReportedAndChangesNothing) {
  // NaN in vx and vz in the tissue ring and the air (10 mm and more from the axis; the lumen
  // section reads to about 8 mm) in frames 0, 5 and 6, and in the magnitude of frame 9 at the
  // grid's corners: reported with count, frames and voxels, and the tables are the clean
  // scan's to the last digit (the corrections leave such voxels out; noise-free tissue has no
  // offset to fit either way).
  for (const std::string ext : kFormats) {
    const Measured clean = measure("clean", ext, [](mri::Flow4D&) {});
    ASSERT_EQ(clean.result.code, 0) << clean.result.output;
    EXPECT_EQ(read_json(clean.dir / "flow" / "mri.json")["non_finite"], nlohmann::json::object());
    std::size_t ring = 0;
    const Measured m = measure("outside", ext, [&](mri::Flow4D& d) {
      for (std::size_t v = 0; v < d.grid.count(); ++v)
        if (radius_of(d, v) >= 10.0 / 1.5) {
          ++ring;
          for (std::size_t f : {0, 5, 6})
            d.frames[f].velocity[0][v] = d.frames[f].velocity[2][v] = std::nanf("");
        }
      const int n = d.grid.size[0] - 1, k = d.grid.size[2] - 1;
      for (const auto& [i, j] : {std::pair{0, 0}, {n, 0}, {0, n}, {n, n}})
        d.frames[9].magnitude[d.grid.linear(i, j, k)] = std::nanf("");
    });
    ASSERT_EQ(m.result.code, 0) << m.result.output;
    for (const char* table : {"flow.csv", "area.csv", "velocity.csv"})
      EXPECT_EQ(read_text(m.dir / "flow" / table), read_text(clean.dir / "flow" / table)) << table;
    const std::string& out = m.result.output;
    EXPECT_NE(out.find(fmt::format("vz ('{}'): {} value(s) of {} are not numbers (NaN or "
                                   "infinite), in frame(s) 0 and 5-6",
                                   m.file("vz", ext), 3 * ring, pipe().grid.count() * 20)),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("lie outside every landmark's lumen section"), std::string::npos) << out;
    const nlohmann::json report = read_json(m.dir / "flow" / "mri.json")["non_finite"];
    ASSERT_TRUE(report.contains("vz")) << report.dump(2);
    EXPECT_EQ(report["vz"]["values"], 3 * ring);
    EXPECT_EQ(report["vz"]["values_per_frame"][5], ring);
    EXPECT_EQ(report["vz"]["values_per_frame"][1], 0);
    EXPECT_EQ(report["vz"]["source"], "'" + m.file("vz", ext) + "'");
    EXPECT_EQ(report["vx"]["values"], 3 * ring);
    EXPECT_EQ(report["magnitude"]["values"], 4);
    EXPECT_EQ(report["magnitude"]["index_box"]["lowest"], (std::array<int, 3>{0, 0, 11}));
    EXPECT_FALSE(report.contains("vy")) << report.dump(2);
  }
}

TEST(MriNonFinite, AMagnitudeThatIsNotANumberAnywhereIsSaidSo) {
  // Was: "background correction: no voxel with signal" (exit 3), naming no file.
  for (const std::string ext : kFormats) {
    const Measured m = measure("magnitude", ext, [](mri::Flow4D& d) {
      for (mri::Frame& f : d.frames)
        std::fill(f.magnitude.begin(), f.magnitude.end(), std::nanf(""));
    });
    EXPECT_EQ(m.result.code, 2) << m.result.output;
    EXPECT_NE(m.result.output.find("every value of the magnitude ('" + m.file("magnitude", ext) +
                                   "') is not a number"),
              std::string::npos)
        << m.result.output;
    EXPECT_EQ(m.result.output.find("no voxel with signal"), std::string::npos) << m.result.output;
  }
}

TEST(MriNonFinite, AMagnitudeOnly4dFolderSaysThePhaseSeriesAreMissing) {
  // A 4D-flow export holding the magnitude series alone was read as a cine scan and refused
  // as a cine of several slices. `mri flow` and `mri cine` on it now say what is missing.
  mri::PipeScan scan = pipe();
  scan.frames = 3;
  const fs::path dir = fresh_dir("mri-nan-magnitude-only");
  mri::write_dicom(mri::synthesize_pipe(scan), dir);
  for (const char* phase : {"vx", "vy", "vz"})
    fs::remove_all(dir / phase);
  geometry::write_landmarks(test_pipe_landmarks(scan), dir / "landmarks.json");
  for (const std::string& args :
       {"mri flow " + dir.string() + " --landmarks " + (dir / "landmarks.json").string() + " -o " +
            (dir / "out").string(),
        "mri cine --at AAo=" + dir.string() + " --landmarks " + (dir / "landmarks.json").string() +
            " -o " + (dir / "out").string()}) {
    const Result r = run_tearflow(args);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("'" + dir.string() +
                            "': a magnitude series alone, 12 slices per "
                            "frame: the phase series are missing"),
              std::string::npos)
        << r.output;
  }
}

TEST(MriNonFinite, PhaseContrastNotANumberInTheVesselIsRefusedElsewhereHarmless) {
  // The 2D path (`mri inflow`) measures through the same planes: a NaN in the vessel's
  // through-plane velocity is refused naming the frame; one in the air changes no flow.
  mri::PipeScan pc = pipe();
  pc.grid = mri::centred_grid(pc.axis_point, mri::rotation({1, 1, 0}, 0.0), {21, 21, 1},
                              {1.5e-3, 1.5e-3, 6e-3});
  pc.encoding = mri::Encoding::through_plane;
  const mri::Flow4D clean = mri::synthesize_pipe(pc);
  const mri::VesselFlow reference = mri::measure_vessel(clean, "AAo", {});
  mri::Flow4D air = clean;
  air.frames[4].velocity[2][0] = std::nanf(""); // corner voxel: air
  const mri::VesselFlow v = mri::measure_vessel(air, "AAo", {});
  EXPECT_EQ(v.flow, reference.flow);
  mri::Flow4D vessel = clean;
  vessel.frames[4].velocity[2][clean.grid.linear(10, 10, 0)] = std::nanf("");
  expect_input_error([&] { mri::measure_vessel(vessel, "AAo", {}); },
                     "landmark 'AAo', frame 4 (t = ");
  expect_input_error([&] { mri::measure_vessel(vessel, "AAo", {}); },
                     "from through-plane velocity; the flow would be wrong");
}

TEST(MriNonFinite, UnwrappingDoesNotCarryANotANumberIntoLaterFrames) {
  // A NaN as the reference made every later frame's jump NaN, and so every later value:
  // one damaged frame became a damaged voxel. The next number is the reference instead.
  mri::Flow4D data = mri::synthesize_pipe(pipe());
  data.venc = 1.0;
  const std::size_t centre = data.grid.linear(10, 10, 6);
  data.frames[0].velocity[2][centre] = std::nanf("");
  data.frames[7].velocity[2][centre] = std::nanf("");
  const mri::Flow4D before = data;
  mri::unwrap_temporal(data);
  for (std::size_t f = 0; f < data.frames.size(); ++f)
    if (f != 0 && f != 7)
      EXPECT_EQ(data.frames[f].velocity[2][centre], before.frames[f].velocity[2][centre])
          << "frame " << f;
}

TEST(MriNonFinite, VoxelComparisonRefusesANotANumberInTheLumen) {
  // `mri compare --scan`: the lumen's voxels of the simulated scan read the MRI's velocity.
  mri::PipeScan scan = pipe();
  scan.frames = 4;
  const mri::Flow4D sim = mri::synthesize_pipe(scan);
  mri::Flow4D measured = sim;
  measured.frames[2].velocity[2][0] = std::nanf(""); // a corner: air, not lumen
  EXPECT_NO_THROW(mri::compare_voxels(sim, measured));
  measured.frames[2].velocity[2][sim.grid.linear(10, 10, 6)] = std::nanf("");
  expect_input_error([&] { mri::compare_voxels(sim, measured); },
                     "mri compare --scan, frame 2 (t = ");
  expect_input_error([&] { mri::compare_voxels(sim, measured); }, "from vz; the speed and angle");
}
