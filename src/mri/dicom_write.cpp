// Writing MRI series as DICOM (image_io.hpp for the conventions): straight through GDCM's
// data-set writer (ITK's writer turns a rescaled MR image into an enhanced MR object; GDCM's
// image writer resets RescaleType and drops private elements), so that the files are classic
// MR images with exactly these elements. One series per measured image: the magnitude, then
// the phase of each encoded direction (4D flow: rl, ap, fh; 2D phase contrast: "in", through
// the slice; cine: none).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <gdcmAttribute.h>
#include <gdcmUIDGenerator.h>
#include <gdcmWriter.h>

#include "core/error.hpp"
#include "mri/image_io.hpp"

namespace tearflow::mri {

namespace fs = std::filesystem;

namespace {

/// Sets a string-valued element (padded to even length as DICOM requires).
void put(gdcm::DataSet& ds, std::uint16_t group, std::uint16_t element, gdcm::VR vr,
         std::string value) {
  if (value.size() % 2)
    value += vr == gdcm::VR::UI ? '\0' : ' ';
  gdcm::DataElement de(gdcm::Tag(group, element));
  de.SetVR(vr);
  de.SetByteValue(value.data(), static_cast<std::uint32_t>(value.size()));
  ds.Replace(de);
}

/// One series to write: its folder, the direction its phase encodes ("" for the magnitude),
/// and the value per voxel of a frame.
struct SeriesPlan {
  std::string folder, direction;
  int component = -1; ///< velocity component; -1 magnitude; 3 the through-plane v . n
};

std::vector<SeriesPlan> series_of(const Flow4D& data, const DicomWriteOptions& options) {
  std::vector<SeriesPlan> plan;
  if (options.write_magnitude)
    plan.push_back({"magnitude", "", -1});
  if (data.encoding == Encoding::velocity_3d) {
    const char* names[] = {"rl", "ap", "fh"};
    for (int c = 0; c < 3; ++c)
      if (c < 2 || options.write_vz)
        plan.push_back({fmt::format("v{}", "xyz"[c]), names[c], c});
  } else if (data.encoding == Encoding::through_plane) {
    plan.push_back({"through", "in", 3});
  }
  return plan;
}

} // namespace

void write_dicom(const Flow4D& data, const fs::path& dir, const DicomWriteOptions& options) {
  data.check("write_dicom");
  const ImageGrid& g = data.grid;
  const bool has_phase = data.encoding != Encoding::magnitude;
  if (has_phase && options.convention == PhaseConvention::classic && options.write_venc &&
      !(data.venc > 0))
    input_error("write_dicom '{}': classic phase images need a venc", dir.string());
  gdcm::UIDGenerator uid;
  const std::string study = uid.Generate(), frame_of_reference = uid.Generate();
  float max_magnitude = 0.0f;
  for (const Frame& f : data.frames)
    for (float m : f.magnitude)
      max_magnitude = std::max(max_magnitude, m);
  if (!(max_magnitude > 0))
    max_magnitude = 1.0f;
  const int venc_cm = static_cast<int>(std::lround(data.venc * 100));
  const bool siemens_venc = options.write_venc && options.convention == PhaseConvention::classic;
  const bool ge_venc = options.write_venc && options.convention == PhaseConvention::rescaled;
  // Siemens' sequence names: fl3d (4D flow), fl2d (2D phase contrast), tfi2d (cine, bSSFP).
  const std::string sequence_kind = data.encoding == Encoding::velocity_3d     ? "fl3d1"
                                    : data.encoding == Encoding::through_plane ? "fl2d1"
                                                                               : "tfi2d1";
  const std::string label = data.encoding == Encoding::velocity_3d     ? "4D flow"
                            : data.encoding == Encoding::through_plane ? "2D flow"
                                                                       : "cine";
  const Vec3& normal = g.direction[2];
  const std::size_t per_slice = std::size_t(g.size[0]) * g.size[1];
  std::vector<std::uint16_t> stored(per_slice);
  const std::vector<SeriesPlan> plan = series_of(data, options);
  for (std::size_t s = 0; s < plan.size(); ++s) {
    const SeriesPlan& series = plan[s];
    const fs::path series_dir = dir / series.folder;
    fs::create_directories(series_dir);
    const std::string series_uid = uid.Generate();
    const bool phase = series.component >= 0,
               classic = options.convention == PhaseConvention::classic;
    const std::string direction = phase ? series.direction : "in";
    const std::string sequence = !has_phase ? sequence_kind
                                 : siemens_venc
                                     ? fmt::format("{}_v{}{}", sequence_kind, venc_cm, direction)
                                     : fmt::format("{}_{}", sequence_kind, direction);
    // Stored values: magnitude 0..4000 over the data's range; classic phase 12 bits,
    // Siemens' RescaleSlope 2 / Intercept -4096, so that x = 2 p - 4096 = v / venc 4096;
    // rescaled phase: 16 bits, v [cm/s] = 0.05 p - 1638.4.
    const int bits = phase && classic ? 12 : 16;
    const double slope = !phase ? 1.0 : (classic ? 2.0 : 0.05);
    const double intercept = !phase ? 0.0 : (classic ? -4096.0 : -1638.4);
    for (std::size_t f = 0; f < data.frames.size(); ++f) {
      const Frame& fr = data.frames[f];
      for (int k = 0; k < g.size[2]; ++k) {
        const std::size_t offset = g.linear(0, 0, k);
        for (std::size_t p = 0; p < per_slice; ++p) {
          const std::size_t v = offset + p;
          double velocity = 0.0;
          if (series.component == 3)
            velocity = along(fr, v, normal);
          else if (phase)
            velocity = fr.velocity[series.component][v];
          double value;
          if (!phase)
            value = std::round(fr.magnitude[v] / max_magnitude * 4000.0);
          else if (classic)
            value = std::round((velocity / data.venc + 1.0) * 2048.0);
          else
            value = std::round((velocity * 100.0 - intercept) / slope);
          stored[p] = static_cast<std::uint16_t>(std::clamp(value, 0.0, (1 << bits) - 1.0));
        }
        gdcm::Writer w;
        gdcm::DataSet& ds = w.GetFile().GetDataSet();
        w.GetFile().GetHeader().SetDataSetTransferSyntax(
            gdcm::TransferSyntax::ExplicitVRLittleEndian);
        const Vec3 o = g.point({0.0, 0.0, double(k)});
        put(ds, 0x0020, 0x0032, gdcm::VR::DS, // DICOM lengths are mm
            fmt::format("{:.10g}\\{:.10g}\\{:.10g}", o[0] * 1e3, o[1] * 1e3, o[2] * 1e3));
        put(ds, 0x0020, 0x0037, gdcm::VR::DS,
            fmt::format("{:.10g}\\{:.10g}\\{:.10g}\\{:.10g}\\{:.10g}\\{:.10g}", g.direction[0][0],
                        g.direction[0][1], g.direction[0][2], g.direction[1][0], g.direction[1][1],
                        g.direction[1][2]));
        // PixelSpacing is row spacing (between rows, along j) \\ column spacing (along i).
        put(ds, 0x0028, 0x0030, gdcm::VR::DS,
            fmt::format("{:.10g}\\{:.10g}", g.spacing[1] * 1e3, g.spacing[0] * 1e3));
        put(ds, 0x0028, 0x0004, gdcm::VR::CS, "MONOCHROME2");
        ds.Replace(gdcm::Attribute<0x0028, 0x0002>{1}.GetAsDataElement()); // samples per pixel
        ds.Replace(gdcm::Attribute<0x0028, 0x0010>{static_cast<std::uint16_t>(g.size[1])}
                       .GetAsDataElement()); // rows
        ds.Replace(gdcm::Attribute<0x0028, 0x0011>{static_cast<std::uint16_t>(g.size[0])}
                       .GetAsDataElement()); // columns
        ds.Replace(gdcm::Attribute<0x0028, 0x0100>{16}.GetAsDataElement());
        ds.Replace(
            gdcm::Attribute<0x0028, 0x0101>{static_cast<std::uint16_t>(bits)}.GetAsDataElement());
        ds.Replace(gdcm::Attribute<0x0028, 0x0102>{static_cast<std::uint16_t>(bits - 1)}
                       .GetAsDataElement());
        ds.Replace(gdcm::Attribute<0x0028, 0x0103>{0}.GetAsDataElement()); // unsigned
        gdcm::DataElement pixels(gdcm::Tag(0x7fe0, 0x0010));
        pixels.SetVR(gdcm::VR::OW);
        pixels.SetByteValue(reinterpret_cast<const char*>(stored.data()),
                            static_cast<std::uint32_t>(per_slice * sizeof(std::uint16_t)));
        ds.Replace(pixels);
        put(ds, 0x0008, 0x0016, gdcm::VR::UI, "1.2.840.10008.5.1.4.1.1.4"); // MR Image Storage
        put(ds, 0x0008, 0x0018, gdcm::VR::UI, uid.Generate());
        put(ds, 0x0008, 0x0008, gdcm::VR::CS,
            phase ? "ORIGINAL\\PRIMARY\\P\\ND" : "ORIGINAL\\PRIMARY\\M\\ND");
        put(ds, 0x0008, 0x0060, gdcm::VR::CS, "MR");
        put(ds, 0x0008, 0x103e, gdcm::VR::LO,
            phase ? fmt::format("{} velocity {}", label, direction)
                  : fmt::format("{} magnitude", label));
        put(ds, 0x0018, 0x0024, gdcm::VR::SH, sequence);
        put(ds, 0x0018, 0x0050, gdcm::VR::DS, fmt::format("{:.6g}", g.spacing[2] * 1e3));
        put(ds, 0x0018, 0x0088, gdcm::VR::DS, fmt::format("{:.6g}", g.spacing[2] * 1e3));
        put(ds, 0x0018, 0x1060, gdcm::VR::DS, fmt::format("{:.6g}", fr.time * 1e3));
        if (data.period > 0) // NominalInterval: the R-R interval the frames span [ms]
          put(ds, 0x0018, 0x1062, gdcm::VR::IS, fmt::format("{}", std::lround(data.period * 1e3)));
        put(ds, 0x0020, 0x000d, gdcm::VR::UI, study);
        put(ds, 0x0020, 0x000e, gdcm::VR::UI, series_uid);
        put(ds, 0x0020, 0x0011, gdcm::VR::IS, std::to_string(s + 1));
        put(ds, 0x0020, 0x0013, gdcm::VR::IS, std::to_string(f * g.size[2] + k + 1));
        put(ds, 0x0020, 0x0052, gdcm::VR::UI, frame_of_reference);
        put(ds, 0x0028, 0x1052, gdcm::VR::DS, fmt::format("{:g}", intercept));
        put(ds, 0x0028, 0x1053, gdcm::VR::DS, fmt::format("{:g}", slope));
        if (phase && !classic)
          put(ds, 0x0028, 0x1054, gdcm::VR::LO, "cm/s");
        if (phase && ge_venc) { // GE: venc in mm/s in a private element
          put(ds, 0x0019, 0x0010, gdcm::VR::LO, "GEMS_ACQU_01");
          put(ds, 0x0019, 0x10cc, gdcm::VR::DS, fmt::format("{:g}", data.venc * 1e3));
        }
        const fs::path file = series_dir / fmt::format("IM_{:04d}_{:04d}.dcm", f, k);
        w.SetFileName(file.string().c_str());
        if (!w.Write())
          input_error("cannot write '{}'", file.string());
      }
    }
  }
}

} // namespace tearflow::mri
