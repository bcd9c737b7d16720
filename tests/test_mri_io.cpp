// 4D-flow MRI files: the analytic pipe through DICOM (both phase conventions) and NIfTI /
// MetaImage volumes and back, flows against the exact ones; the readers' errors.
#include <cmath>

#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "mri/image_io.hpp"
#include "mri/plane_flow.hpp"
#include "mri_support.hpp"

using namespace tearflow;
using namespace tearflow::testing;

TEST(MriDicom, RoundTripKeepsGeometryAndFlows) {
  // Issue 9: noise-free, 1.5 mm voxels, 8 across -> DICOM -> read -> plane flow within 2 %
  // at every frame. Oblique (25 degrees) so that position and orientation are exercised.
  const mri::PipeScan scan = test_pipe_scan(25.0);
  const mri::Flow4D data = mri::synthesize_pipe(scan);
  const auto dir = fresh_dir("mri-dicom");
  mri::write_dicom(data, dir);
  const mri::Flow4D back = mri::read_dicom(dir);
  EXPECT_TRUE(back.grid.same_as(data.grid));
  EXPECT_NEAR(back.venc, scan.venc, 1e-12);
  ASSERT_EQ(back.frames.size(), data.frames.size());
  // 12-bit phase: one step is venc / 2048; the rounding error at most half of it.
  double worst_v = 0.0;
  for (std::size_t f = 0; f < data.frames.size(); ++f) {
    EXPECT_NEAR(back.frames[f].time, data.frames[f].time, 1e-6);
    for (int c = 0; c < 3; ++c)
      for (std::size_t v = 0; v < data.grid.count(); ++v)
        worst_v = std::max(worst_v, double(std::abs(back.frames[f].velocity[c][v] -
                                                    data.frames[f].velocity[c][v])));
  }
  EXPECT_LE(worst_v, 0.5 * scan.venc / 2048 * 1.001);
  const double worst = worst_flow_error(scan, back);
  std::printf("DICOM round trip: worst velocity %.2e m/s, worst frame flow error %.3f %%\n",
              worst_v, 100 * worst);
  EXPECT_LT(worst, 0.02);
}

TEST(MriDicom, RescaledToVelocityWithNoisyData) {
  // RescaleSlope/Intercept to cm/s (0.05 cm/s steps); SNR 20 in the aorta-sized pipe: 5 %.
  const mri::PipeScan scan = test_pipe_scan(0.0, 20.0, 9e-3);
  const auto dir = fresh_dir("mri-dicom-rescaled");
  mri::write_dicom(mri::synthesize_pipe(scan), dir, {mri::PhaseConvention::rescaled, false});
  const mri::Flow4D back = mri::read_dicom(dir);
  EXPECT_EQ(back.venc, 0.0); // none written, none needed
  const double worst = worst_flow_error(scan, back);
  std::printf("DICOM rescaled, SNR 20: worst frame flow error %.3f %%\n", 100 * worst);
  EXPECT_LT(worst, 0.05);
}

TEST(MriDicom, AnisotropicVoxelsAndGeVenc) {
  // Voxels of 1.4 x 1.6 x 1.8 mm on an oblique grid: PixelSpacing's order (rows, then
  // columns) and the slice spacing must come back on their axes; venc from GE's element.
  mri::PipeScan scan = test_pipe_scan();
  scan.frames = 3;
  scan.grid = mri::centred_grid(scan.axis_point, mri::rotation({0, 1, 1}, 30.0), {22, 19, 9},
                                {1.4e-3, 1.6e-3, 1.8e-3});
  const mri::Flow4D data = mri::synthesize_pipe(scan);
  const auto dir = fresh_dir("mri-dicom-aniso");
  mri::write_dicom(data, dir, {mri::PhaseConvention::rescaled, true});
  const mri::Flow4D back = mri::read_dicom(dir);
  EXPECT_TRUE(back.grid.same_as(data.grid));
  EXPECT_NEAR(back.venc, scan.venc, 1e-12);
  // 0.05 cm/s steps: half a step at most.
  for (std::size_t v = 0; v < data.grid.count(); ++v)
    ASSERT_NEAR(back.frames[2].velocity[2][v], data.frames[2].velocity[2][v], 2.5e-4 * 1.001);
}

TEST(MriDicom, BadInputSaysWhatIsExpected) {
  mri::PipeScan scan = test_pipe_scan();
  scan.frames = 4;
  const mri::Flow4D data = mri::synthesize_pipe(scan);
  { // no venc anywhere
    const auto dir = fresh_dir("mri-dicom-novenc");
    mri::write_dicom(data, dir, {mri::PhaseConvention::classic, false});
    expect_input_error([&] { mri::read_dicom(dir); }, "no venc");
    EXPECT_NO_THROW(mri::read_dicom(dir, {1.0})); // --venc supplies it
  }
  { // a missing phase series
    const auto dir = fresh_dir("mri-dicom-novz");
    mri::DicomWriteOptions o;
    o.write_vz = false;
    mri::write_dicom(data, dir, o);
    expect_input_error([&] { mri::read_dicom(dir); }, "no phase fh (z) series");
  }
  { // a file cut short (GDCM read it, warning without the file's name) and an empty one
    // (skipped as not DICOM, so a slice went missing): each refused, naming the file
    const auto dir = fresh_dir("mri-dicom-cut");
    mri::write_dicom(data, dir);
    const auto cut = dir / "vy" / "IM_0003_0002.dcm";
    std::filesystem::resize_file(cut, std::filesystem::file_size(cut) - 300);
    expect_input_error([&] { mri::read_dicom(dir); }, "'" + cut.string() + "': cut short");
    mri::write_dicom(data, dir);
    const auto empty = dir / "vx" / "IM_0002_0001.dcm";
    std::filesystem::resize_file(empty, 0);
    expect_input_error([&] { mri::read_dicom(dir); }, "'" + empty.string() + "': an empty file");
  }
  { // a series with fewer frames
    const auto dir = fresh_dir("mri-dicom-frames");
    mri::write_dicom(data, dir);
    for (int k = 0; k < scan.grid.size[2]; ++k)
      std::filesystem::remove(dir / "vy" / fmt::format("IM_0003_{:04d}.dcm", k));
    expect_input_error([&] { mri::read_dicom(dir); }, "phase ap (y) series has 3 frames");
  }
  { // a series on another grid
    const auto dir = fresh_dir("mri-dicom-grid");
    mri::write_dicom(data, dir);
    mri::Flow4D moved = data;
    moved.grid.origin = moved.grid.origin + Vec3{0.002, 0, 0};
    const auto other = fresh_dir("mri-dicom-grid-other");
    mri::write_dicom(moved, other);
    std::filesystem::remove_all(dir / "vx");
    std::filesystem::rename(other / "vx", dir / "vx");
    expect_input_error([&] { mri::read_dicom(dir); }, "share one grid");
  }
  expect_input_error([&] { mri::read_dicom("/nonexistent-mri"); }, "no such folder");
}

TEST(MriVolumes, NiftiAndMetaImageRoundTrip) {
  const mri::PipeScan scan = test_pipe_scan(25.0);
  const mri::Flow4D data = mri::synthesize_pipe(scan);
  for (const std::string ext : {".nii.gz", ".mha"}) {
    const auto dir = fresh_dir("mri-volumes");
    mri::write_volumes(data, dir, ext);
    const mri::Flow4D back = mri::read_flow_data(dir);
    EXPECT_TRUE(back.grid.same_as(data.grid)) << ext;
    ASSERT_EQ(back.frames.size(), data.frames.size());
    EXPECT_NEAR(back.frames[3].time, data.frames[3].time, 1e-6);
    EXPECT_EQ(back.frames[7].velocity[2], data.frames[7].velocity[2]) << ext; // float32 exact
    EXPECT_LT(worst_flow_error(scan, back), 0.02) << ext;
    std::filesystem::remove(dir / ("vy" + ext));
    expect_input_error([&] { mri::read_flow_data(dir); }, "no vy volume");
  }
}

TEST(MriVolumes, ATruncatedVolumeIsRefusedNamingIt) {
  // The probe's truncated .nii.gz was read and failed later ("no signal at the lumen point").
  const mri::Flow4D data = mri::synthesize_pipe(test_pipe_scan(25.0));
  for (const std::string ext : {".nii.gz", ".nii", ".mha"}) {
    const auto dir = fresh_dir("mri-volumes-cut");
    mri::write_volumes(data, dir, ext);
    const auto file = dir / ("vz" + ext);
    std::filesystem::resize_file(file, std::filesystem::file_size(file) * 6 / 10);
    expect_input_error([&] { mri::read_flow_data(dir); }, "'" + file.string() + "': cut short");
  }
}

TEST(MriCommand, SynthesizeFlowCompareEndToEnd) {
  // The three subcommands chained on a small noisy oblique scan with an injected background:
  // the measured flows against the exact ones (synthesize writes them as exact/flow.csv).
  const auto dir = fresh_dir("mri-cli");
  const std::string scan = (dir / "scan").string(), flow = (dir / "flow").string();
  auto r = run_tearflow("mri synthesize -o " + scan +
                        " --radius 9mm --size 32,32,8 --frames 8 --snr 20 --rotate 20 "
                        "--background 0.05m/s --venc 1m/s");
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_tearflow("mri flow " + scan + "/images --landmarks " + scan + "/landmarks.json -o " +
                   flow);
  ASSERT_EQ(r.code, 0) << r.output;
  const auto report = read_json(dir / "flow" / "mri.json");
  EXPECT_GT(report["background"]["static_voxels"].get<int>(), 1000) << report.dump(2);
  r = run_tearflow("mri compare " + scan + "/exact " + flow + " -o " + (dir / "cmp").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto c = read_json(dir / "cmp" / "compare.json");
  for (const char* name : {"inlet", "outlet"}) {
    const auto& l = c["landmarks"][name];
    // The 5 % per frame of issue 9 (SNR 20), so also for the bias; r of a waveform measured
    // that well is far above 0.99.
    const double mean = l["mean_flow_simulation_mL_per_s"].get<double>();
    EXPECT_LT(std::abs(l["difference_mean_mL_per_s"].get<double>()), 0.05 * mean) << c.dump(2);
    EXPECT_GT(l["correlation"].get<double>(), 0.99) << c.dump(2);
  }
  // The tables are the measured layout `tearflow analyze` reads.
  r = run_tearflow("analyze " + flow + " -o " + (dir / "analysis").string());
  EXPECT_EQ(r.code, 0) << r.output;
}

TEST(MriCommand, BadInputExitsNonZeroWithTheReason) {
  const auto dir = fresh_dir("mri-cli-bad");
  std::filesystem::create_directories(dir);
  auto r =
      run_tearflow("mri flow " + dir.string() + " --landmarks x.json -o " + (dir / "out").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("no DICOM file"), std::string::npos) << r.output;
  r = run_tearflow("mri synthesize -o " + (dir / "s").string() + " --voxel 1.5furlong");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--voxel"), std::string::npos) << r.output;
  // Issue 28: --size 2000,2000,200 allocated 9 GB before a bare std::bad_alloc. The estimate
  // (4 float images x 8e8 voxels x 20 frames = 256 GB) is refused before any allocation.
  r = run_tearflow("mri synthesize -o " + (dir / "s").string() + " --size 2000,2000,200");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--size 2000 x 2000 x 200 voxels x 20 frames needs about 256.0 GB"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "s"));
  // Within the estimate's bound but beyond what the process may have (ulimit -v 1.2 GB for
  // 2 GB of images): the error says so in words, not as a bare std::bad_alloc.
  r = run_tearflow("mri synthesize -o " + (dir / "s").string() + " --size 250,250,100",
                   "ulimit -v 1200000;");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("error: out of memory: the input asks for more memory"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
}
