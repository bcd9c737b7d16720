// 4D-flow DICOM through ITK's GDCM image I/O (image_io.hpp for the conventions). Each file is
// one slice of one frame of one series; ITK reads its pixels (rescaled by RescaleSlope and
// Intercept), position, orientation and spacing, and its tags as strings. The files are
// grouped into series (magnitude, x, y, z phase), frames (TriggerTime) and slices (position
// along the slice normal), checked to share one geometry, and assembled into a Flow4D.
#include "mri/image_io.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <regex>
#include <thread>

#include <fmt/format.h>
#include <gdcmAttribute.h>
#include <gdcmReader.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>
#include <gdcmWriter.h>
#include <itkGDCMImageIO.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkMetaDataObject.h>

#include "core/error.hpp"

namespace tearflow::mri {

namespace fs = std::filesystem;
using Slice = itk::Image<float, 3>;

namespace {

const char* const kComponentNames[] = {"rl", "ap", "fh"};

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  const auto e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::optional<double> number(const std::string& s) {
  try {
    return std::stod(s);
  } catch (...) {
    return std::nullopt;
  }
}

} // namespace

// ---------------------------------------------------------------------------------------
// Writing: straight through GDCM's data-set writer (ITK's writer turns a rescaled MR image
// into an enhanced MR object; GDCM's image writer resets RescaleType and drops private
// elements), so that the files are classic MR images with exactly these elements.

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

} // namespace

void write_dicom(const Flow4D& data, const fs::path& dir, const DicomWriteOptions& options) {
  data.check("write_dicom");
  const ImageGrid& g = data.grid;
  if (options.convention == PhaseConvention::classic && options.write_venc && !(data.venc > 0))
    input_error("write_dicom '{}': classic phase images need a venc", dir.string());
  gdcm::UIDGenerator uid;
  const std::string study = uid.Generate(), frame_of_reference = uid.Generate();
  float max_magnitude = 0.0f;
  for (const Frame& f : data.frames)
    for (float m : f.magnitude)
      max_magnitude = std::max(max_magnitude, m);
  const int venc_cm = static_cast<int>(std::lround(data.venc * 100));
  const bool siemens_venc = options.write_venc && options.convention == PhaseConvention::classic;
  const bool ge_venc = options.write_venc && options.convention == PhaseConvention::rescaled;
  const std::size_t per_slice = std::size_t(g.size[0]) * g.size[1];
  std::vector<std::uint16_t> stored(per_slice);
  for (int s = 0; s < 4; ++s) {
    if ((s == 0 && !options.write_magnitude) || (s == 3 && !options.write_vz))
      continue;
    const std::string name = s == 0 ? "magnitude" : fmt::format("v{}", "xyz"[s - 1]);
    const fs::path series_dir = dir / name;
    fs::create_directories(series_dir);
    const std::string series_uid = uid.Generate();
    const std::string direction = s == 0 ? "in" : kComponentNames[s - 1];
    const std::string sequence = siemens_venc ? fmt::format("fl3d1_v{}{}", venc_cm, direction)
                                              : fmt::format("fl3d1_{}", direction);
    const bool phase = s > 0, classic = options.convention == PhaseConvention::classic;
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
          double value;
          if (!phase)
            value = std::round(fr.magnitude[offset + p] / max_magnitude * 4000.0);
          else if (classic)
            value = std::round((fr.velocity[s - 1][offset + p] / data.venc + 1.0) * 2048.0);
          else
            value = std::round((fr.velocity[s - 1][offset + p] * 100.0 - intercept) / slope);
          stored[p] = static_cast<std::uint16_t>(std::clamp(value, 0.0, (1 << bits) - 1.0));
        }
        // The data set element by element, written by gdcm::Writer as it is (GDCM's image
        // writer would override RescaleType and drop private elements).
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
            phase ? fmt::format("4D flow velocity {}", direction) : "4D flow magnitude");
        put(ds, 0x0018, 0x0024, gdcm::VR::SH, sequence);
        put(ds, 0x0018, 0x0050, gdcm::VR::DS, fmt::format("{:.6g}", g.spacing[2] * 1e3));
        put(ds, 0x0018, 0x0088, gdcm::VR::DS, fmt::format("{:.6g}", g.spacing[2] * 1e3));
        put(ds, 0x0018, 0x1060, gdcm::VR::DS, fmt::format("{:.6g}", fr.time * 1e3));
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

// ---------------------------------------------------------------------------------------
// Reading

namespace {

/// What one file holds.
struct SliceFile {
  fs::path file;
  std::string series_uid, image_type, sequence, description, rescale_type;
  double trigger_ms = 0.0, intercept = 0.0;
  int bits_stored = 12;
  std::optional<double> venc; ///< [m/s]
  bool enhanced = false;
  Slice::Pointer image;
};

std::string tag(const itk::MetaDataDictionary& d, const std::string& key) {
  std::string v;
  itk::ExposeMetaData<std::string>(d, key, v);
  return trim(v);
}

/// Venc from the conventions of image_io.hpp, in m/s.
std::optional<double> venc_of(const itk::MetaDataDictionary& d) {
  static const std::regex siemens(R"(_v(\d+)(in|rl|ap|fh|through|[a-z]*)$)", std::regex::icase);
  std::smatch m;
  const std::string sequence = tag(d, "0018|0024");
  if (std::regex_search(sequence, m, siemens))
    return std::stod(m[1]) * 1e-2; // cm/s
  if (auto v = number(tag(d, "0019|10cc")); v && *v > 0)
    return *v * 1e-3; // GE: mm/s
  if (auto v = number(tag(d, "2001|101a")); v && std::abs(*v) > 0)
    return std::abs(*v) * 1e-2; // Philips: cm/s (first of the three)
  if (auto v = number(tag(d, "0018|9217")); v && *v > 0)
    return *v * 1e-2; // enhanced MR Velocity Encoding Maximum Value: cm/s
  return std::nullopt;
}

/// InputError naming the file when its pixel data is shorter than its rows, columns, frames
/// and bits announce: GDCM reads such a file, warning "Incomplete Pixel Data found" without
/// the file's name, and every frame's flow changed (the probe's truncated file).
void check_pixel_data(const fs::path& file) {
  gdcm::Reader r;
  r.SetFileName(file.c_str());
  if (!r.Read())
    input_error("'{}': not a readable DICOM file", file.string());
  const gdcm::DataSet& ds = r.GetFile().GetDataSet();
  const auto value = [&](std::uint16_t group, std::uint16_t element, double fallback) {
    const gdcm::Tag t(group, element);
    if (!ds.FindDataElement(t) || ds.GetDataElement(t).IsEmpty())
      return fallback;
    const gdcm::ByteValue* v = ds.GetDataElement(t).GetByteValue();
    if (v == nullptr)
      return fallback;
    if (t.GetElement() == 0x0008) // NumberOfFrames: an IS string
      return number(std::string(v->GetPointer(), v->GetLength())).value_or(fallback);
    std::uint16_t u = 0; // US
    std::memcpy(&u, v->GetPointer(), std::min<std::size_t>(2, v->GetLength()));
    return static_cast<double>(u);
  };
  const auto image = static_cast<std::uint32_t>(
      value(0x0028, 0x0010, 0) * value(0x0028, 0x0011, 0) * value(0x0028, 0x0008, 1) *
      value(0x0028, 0x0002, 1) * std::ceil(value(0x0028, 0x0100, 16) / 8.0));
  if (image == 0 || r.GetFile().GetHeader().GetDataSetTransferSyntax().IsEncapsulated())
    return; // compressed fragments: the codec checks them
  // GDCM pads a short value to its declared length, so the bytes on disk decide: the pixel
  // data's element (tag 7fe0,0010, little endian; explicit VR OW/OB with 12 header bytes or
  // implicit with 8) declaring the image's length, and what follows it in the file.
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const std::string tag("\xe0\x7f\x10\x00", 4);
  for (std::size_t at = bytes.find(tag); at != std::string::npos; at = bytes.find(tag, at + 1)) {
    const auto length_at = [&](std::size_t offset) {
      std::uint32_t l = 0;
      if (offset + 4 <= bytes.size())
        std::memcpy(&l, bytes.data() + offset, 4);
      return l;
    };
    const bool explicit_vr =
        bytes.compare(at + 4, 2, "OW") == 0 || bytes.compare(at + 4, 2, "OB") == 0;
    const std::size_t header = explicit_vr ? 12 : 8;
    const std::uint32_t declared = length_at(at + header - 4);
    if (declared != image + (image % 2))
      continue;
    const std::size_t present = bytes.size() - std::min(bytes.size(), at + header);
    if (present < image)
      input_error("'{}': cut short: {} bytes of pixel data where its rows, columns, frames and "
                  "bits announce {} (a truncated copy?)",
                  file.string(), present, image);
    return;
  }
}

SliceFile read_slice(const fs::path& file) {
  check_pixel_data(file);
  auto io = itk::GDCMImageIO::New();
  io->LoadPrivateTagsOn();
  auto reader = itk::ImageFileReader<Slice>::New();
  reader->SetImageIO(io);
  reader->SetFileName(file.string());
  try {
    reader->Update();
  } catch (const itk::ExceptionObject& e) {
    input_error("'{}': not a readable DICOM image ({})", file.string(), e.GetDescription());
  }
  const itk::MetaDataDictionary& d = io->GetMetaDataDictionary();
  SliceFile s;
  s.file = file;
  s.series_uid = tag(d, "0020|000e");
  s.image_type = tag(d, "0008|0008");
  s.sequence = tag(d, "0018|0024");
  s.description = tag(d, "0008|103e");
  s.rescale_type = lower(tag(d, "0028|1054"));
  s.trigger_ms = number(tag(d, "0018|1060")).value_or(0.0);
  s.intercept = number(tag(d, "0028|1052")).value_or(0.0);
  s.bits_stored = static_cast<int>(number(tag(d, "0028|0101")).value_or(12));
  s.venc = venc_of(d);
  const std::string sop_class = tag(d, "0008|0016");
  s.enhanced = sop_class == "1.2.840.10008.5.1.4.1.1.4.1" || // Enhanced MR Image Storage
               number(tag(d, "0028|0008")).value_or(1) > 1;  // several frames in one file
  s.image = reader->GetOutput();
  return s;
}

/// 0 magnitude, 1..3 the phase component x, y, z; -1 unknown.
int series_role(const SliceFile& s) {
  std::vector<std::string> parts;
  std::string part;
  for (char c : s.image_type + "\\") {
    if (c == '\\') {
      parts.push_back(trim(part));
      part.clear();
    } else {
      part += c;
    }
  }
  const bool magnitude = parts.size() > 2 && (parts[2] == "M" || parts[2] == "MAG");
  const bool phase =
      parts.size() > 2 && (parts[2] == "P" || parts[2] == "PHASE" || parts[2] == "VELOCITY");
  if (magnitude)
    return 0;
  if (!phase)
    return -1;
  for (const std::string& text : {lower(s.sequence), lower(s.description)}) {
    for (int c = 0; c < 3; ++c) {
      const std::string suffix = kComponentNames[c];
      if (text.size() >= 2 && text.compare(text.size() - 2, 2, suffix) == 0)
        return c + 1;
    }
  }
  return -2; // a phase series whose direction cannot be told
}

/// The frames of one series: slices per trigger time, sorted along the slice normal.
struct Series {
  std::string name;
  std::vector<double> times_ms;
  std::vector<std::vector<SliceFile*>> frames;
};

Series organise(const std::string& name, std::vector<SliceFile*> files) {
  Series s;
  s.name = name;
  std::map<long, std::vector<SliceFile*>> by_time; // trigger time in 1/100 ms
  for (SliceFile* f : files)
    by_time[std::lround(f->trigger_ms * 100)].push_back(f);
  for (auto& [t, slices] : by_time) {
    const auto& dir = slices.front()->image->GetDirection();
    auto along = [&](SliceFile* f) {
      const auto& o = f->image->GetOrigin();
      return o[0] * dir(0, 2) + o[1] * dir(1, 2) + o[2] * dir(2, 2);
    };
    std::sort(slices.begin(), slices.end(),
              [&](SliceFile* a, SliceFile* b) { return along(a) < along(b); });
    s.times_ms.push_back(t / 100.0);
    s.frames.push_back(std::move(slices));
  }
  return s;
}

/// The grid of one frame's slices; InputError naming `where` for uneven slices.
ImageGrid frame_grid(const std::vector<SliceFile*>& slices, const std::string& where) {
  const Slice* first = slices.front()->image.GetPointer();
  const auto size = first->GetLargestPossibleRegion().GetSize();
  ImageGrid g;
  g.size = {static_cast<int>(size[0]), static_cast<int>(size[1]), static_cast<int>(slices.size())};
  for (int r = 0; r < 3; ++r) {
    g.origin[r] = first->GetOrigin()[r] * 1e-3;
    for (int a = 0; a < 3; ++a)
      g.direction[a][r] = first->GetDirection()(r, a);
  }
  g.spacing = {first->GetSpacing()[0] * 1e-3, first->GetSpacing()[1] * 1e-3, 0.0};
  if (slices.size() > 1) {
    const Vec3 last{slices.back()->image->GetOrigin()[0] * 1e-3,
                    slices.back()->image->GetOrigin()[1] * 1e-3,
                    slices.back()->image->GetOrigin()[2] * 1e-3};
    g.spacing[2] = dot(last - g.origin, g.direction[2]) / (slices.size() - 1);
  } else {
    g.spacing[2] = first->GetSpacing()[2] * 1e-3;
  }
  if (!(g.spacing[2] > 0))
    input_error("{}: two slices at one position", where);
  // Every slice where the grid puts it, with the same size and orientation.
  for (std::size_t k = 0; k < slices.size(); ++k) {
    const Slice* im = slices[k]->image.GetPointer();
    const Vec3 o{im->GetOrigin()[0] * 1e-3, im->GetOrigin()[1] * 1e-3, im->GetOrigin()[2] * 1e-3};
    const Vec3 d = o - g.point({0, 0, double(k)});
    bool same = im->GetLargestPossibleRegion().GetSize() == size &&
                std::sqrt(dot(d, d)) < 1e-3 * g.spacing[2] &&
                std::abs(im->GetSpacing()[0] - first->GetSpacing()[0]) < 1e-6 &&
                std::abs(im->GetSpacing()[1] - first->GetSpacing()[1]) < 1e-6;
    for (int r = 0; r < 3 && same; ++r)
      for (int a = 0; a < 2; ++a)
        same = same && std::abs(im->GetDirection()(r, a) - first->GetDirection()(r, a)) < 1e-5;
    if (!same)
      input_error("{}: slice '{}' is not on the grid of the others (equal size, orientation and "
                  "spacing, evenly spaced positions along the normal are expected)",
                  where, slices[k]->file.string());
  }
  return g;
}

} // namespace

Flow4D read_dicom(const fs::path& dir, const ReadOptions& options) {
  if (!fs::is_directory(dir))
    input_error("'{}': no such folder (a folder of 4D-flow DICOM files is expected)", dir.string());
  // GDCM's warnings name no file ("Incomplete Pixel Data found"); what they warn of that
  // matters is checked here and said with the file (check_pixel_data, the empty file).
  struct QuietGdcm {
    bool was = gdcm::Trace::GetWarningFlag();
    QuietGdcm() { gdcm::Trace::WarningOff(); }
    ~QuietGdcm() { gdcm::Trace::SetWarning(was); }
  } quiet;
  std::vector<fs::path> paths;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file())
      paths.push_back(e.path());
  std::sort(paths.begin(), paths.end());
  // The files are independent: read on every core (each thread its own ITK objects); the
  // first error in file order is the one reported.
  std::vector<std::optional<SliceFile>> slots(paths.size());
  std::vector<std::exception_ptr> errors(paths.size());
  const unsigned workers = std::max(1u, std::min(4u, std::thread::hardware_concurrency()));
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    auto probe = itk::GDCMImageIO::New();
    for (std::size_t i = next++; i < paths.size(); i = next++) {
      try {
        // Not DICOM: skipped (notes, DICOMDIR); but an empty file is a failed copy, whose
        // slice would be missing from its series.
        if (fs::file_size(paths[i]) == 0)
          input_error("'{}': an empty file in the DICOM folder (a failed copy?)",
                      paths[i].string());
        if (probe->CanReadFile(paths[i].string().c_str()))
          slots[i] = read_slice(paths[i]);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> threads;
  for (unsigned t = 1; t < workers; ++t)
    threads.emplace_back(work);
  work();
  for (std::thread& t : threads)
    t.join();
  std::vector<SliceFile> files;
  files.reserve(paths.size());
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (errors[i])
      std::rethrow_exception(errors[i]);
    if (slots[i])
      files.push_back(std::move(*slots[i]));
  }
  slots.clear();
  if (files.empty())
    input_error("'{}': no DICOM file in the folder", dir.string());
  for (const SliceFile& f : files)
    if (f.enhanced)
      input_error("'{}': an enhanced MR multi-frame object; only classic MR images (one file "
                  "per slice and frame) are read - convert it to classic images first",
                  f.file.string());

  // Four series by role.
  std::array<std::map<std::string, std::vector<SliceFile*>>, 4> roles;
  for (SliceFile& f : files) {
    const int role = series_role(f);
    if (role == -2)
      input_error("'{}' (series '{}'): a phase image whose velocity direction is not named; its "
                  "SequenceName or SeriesDescription must end in rl, ap or fh",
                  f.file.string(), f.description);
    if (role >= 0)
      roles[role][f.series_uid].push_back(&f);
  }
  const char* role_names[] = {"magnitude", "phase rl (x)", "phase ap (y)", "phase fh (z)"};
  std::array<Series, 4> series;
  for (int r = 0; r < 4; ++r) {
    if (roles[r].empty())
      input_error("'{}': no {} series; 4D flow needs one magnitude series (ImageType M) and three "
                  "phase series (ImageType P) whose SequenceName or SeriesDescription ends in "
                  "rl, ap and fh",
                  dir.string(), role_names[r]);
    if (roles[r].size() > 1)
      input_error("'{}': {} {} series (SeriesInstanceUIDs); one of each is expected", dir.string(),
                  roles[r].size(), role_names[r]);
    series[r] = organise(role_names[r], roles[r].begin()->second);
  }

  // One frame count, one grid, one slice count.
  const std::string where0 = fmt::format("'{}', {} series", dir.string(), role_names[0]);
  const ImageGrid grid = frame_grid(series[0].frames[0], where0);
  for (int r = 0; r < 4; ++r) {
    if (series[r].frames.size() != series[0].frames.size())
      input_error("'{}': the {} series has {} frames (trigger times), the magnitude {}; every "
                  "series must hold the same frames",
                  dir.string(), role_names[r], series[r].frames.size(), series[0].frames.size());
    for (std::size_t f = 0; f < series[r].frames.size(); ++f) {
      const std::string where = fmt::format("'{}', {} series, frame {} ({} ms)", dir.string(),
                                            role_names[r], f, series[r].times_ms[f]);
      if (!frame_grid(series[r].frames[f], where).same_as(grid))
        input_error("{}: its slices differ from the magnitude's first frame in number, "
                    "position, orientation or spacing; all series and frames must share one "
                    "grid",
                    where);
      if (std::abs(series[r].times_ms[f] - series[0].times_ms[f]) > 0.5)
        input_error("{}: trigger time differs from the magnitude's ({} ms)", where,
                    series[0].times_ms[f]);
    }
  }

  // Venc and the phase-to-velocity mapping per component.
  Flow4D out;
  out.grid = grid;
  std::array<std::optional<double>, 3> venc;
  std::array<double, 3> velocity_unit{}; // rescaled-to-velocity: m/s per unit, else 0
  for (int c = 0; c < 3; ++c) {
    const SliceFile& f = *series[c + 1].frames[0][0];
    venc[c] = options.venc > 0 ? std::optional<double>(options.venc) : f.venc;
    if (f.rescale_type == "cm/s" || f.rescale_type == "cm/sec")
      velocity_unit[c] = 1e-2;
    else if (f.rescale_type == "mm/s")
      velocity_unit[c] = 1e-3;
    else if (f.rescale_type == "m/s")
      velocity_unit[c] = 1.0;
    if (velocity_unit[c] == 0 && !venc[c])
      input_error("'{}', {} series (SequenceName '{}'): no venc. Classic phase images need it "
                  "from the SequenceName ('..._v<cm/s><dir>'), GE's (0019,10cc), Philips' "
                  "(2001,101a) or (0018,9217), or from --venc; images rescaled to velocity need "
                  "RescaleType 'cm/s', 'mm/s' or 'm/s'",
                  dir.string(), role_names[c + 1], f.sequence);
    if (venc[c])
      out.venc = std::max(out.venc, *venc[c]);
  }
  const std::size_t per_slice = std::size_t(grid.size[0]) * grid.size[1];
  for (std::size_t f = 0; f < series[0].frames.size(); ++f) {
    Frame fr;
    fr.time = series[0].times_ms[f] * 1e-3;
    fr.magnitude.resize(grid.count());
    for (auto& v : fr.velocity)
      v.resize(grid.count());
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < grid.size[2]; ++k) {
        const SliceFile& sf = *series[r].frames[f][k];
        const float* px = sf.image->GetBufferPointer();
        float* dst = r == 0 ? fr.magnitude.data() : fr.velocity[r - 1].data();
        dst += grid.linear(0, 0, k);
        if (r == 0) {
          std::copy(px, px + per_slice, dst);
          continue;
        }
        const int c = r - 1;
        if (velocity_unit[c] > 0) {
          for (std::size_t p = 0; p < per_slice; ++p)
            dst[p] = static_cast<float>(px[p] * velocity_unit[c]);
        } else if (sf.intercept < 0) { // x in [-|b|, |b|)
          const double scale = *venc[c] / -sf.intercept;
          for (std::size_t p = 0; p < per_slice; ++p)
            dst[p] = static_cast<float>(px[p] * scale);
        } else { // x in [0, 2^bits)
          const double half = std::ldexp(1.0, sf.bits_stored - 1);
          for (std::size_t p = 0; p < per_slice; ++p)
            dst[p] = static_cast<float>((px[p] - half) / half * *venc[c]);
        }
      }
    out.frames.push_back(std::move(fr));
  }
  if (out.frames.size() > 1)
    out.frame_window = (out.frames.back().time - out.frames.front().time) / (out.frames.size() - 1);
  out.check(dir.string());
  return out;
}

} // namespace tearflow::mri
