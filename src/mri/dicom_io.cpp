// Reading MRI DICOM through ITK's GDCM image I/O (image_io.hpp for the conventions). Each file
// is one slice of one frame of one series; ITK reads its pixels (rescaled by RescaleSlope and
// Intercept), position, orientation and spacing, and its tags as strings. The files are
// grouped into series (magnitude; x, y, z phase for 4D flow, or one through-plane phase for 2D
// phase contrast, or none for cine), frames (TriggerTime) and slices (position along the slice
// normal), checked to share one geometry, and assembled into a Flow4D. The writer is
// dicom_write.cpp.
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
#include <gdcmReader.h>
#include <gdcmTrace.h>
#include <itkGDCMImageIO.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkMetaDataObject.h>

#include "core/error.hpp"
#include "mri/non_finite.hpp"

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
// Reading

namespace {

/// What one file holds.
struct SliceFile {
  fs::path file;
  std::string series_uid, image_type, sequence, description, rescale_type;
  double trigger_ms = 0.0, intercept = 0.0, nominal_interval_ms = 0.0;
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
  s.nominal_interval_ms = number(tag(d, "0018|1062")).value_or(0.0);
  s.bits_stored = static_cast<int>(number(tag(d, "0028|0101")).value_or(12));
  s.venc = venc_of(d);
  const std::string sop_class = tag(d, "0008|0016");
  s.enhanced = sop_class == "1.2.840.10008.5.1.4.1.1.4.1" || // Enhanced MR Image Storage
               number(tag(d, "0028|0008")).value_or(1) > 1;  // several frames in one file
  s.image = reader->GetOutput();
  return s;
}

/// 0 magnitude, 1..3 the phase component x, y, z, 4 the through-plane phase of a 2D scan
/// (SequenceName or SeriesDescription ending in "in" or "through": Siemens' fl2d1_v150in);
/// -1 not an MR magnitude or phase image, -2 a phase image of no direction known.
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
  const auto ends_with = [](const std::string& text, const std::string& suffix) {
    return text.size() >= suffix.size() &&
           text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  for (const std::string& text : {lower(s.sequence), lower(s.description)}) {
    for (int c = 0; c < 3; ++c)
      if (ends_with(text, kComponentNames[c]))
        return c + 1;
    if (ends_with(text, "in") || ends_with(text, "through"))
      return 4;
  }
  return -2;
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

  // The series by role; which are present says what the scan is.
  std::array<std::map<std::string, std::vector<SliceFile*>>, 5> roles;
  for (SliceFile& f : files) {
    const int role = series_role(f);
    if (role == -2)
      input_error("'{}' (series '{}'): a phase image whose velocity direction is not named; its "
                  "SequenceName or SeriesDescription must end in rl, ap or fh (4D flow) or in, "
                  "through (2D through-plane phase contrast)",
                  f.file.string(), f.description);
    if (role >= 0)
      roles[role][f.series_uid].push_back(&f);
  }
  const char* role_names[] = {"magnitude", "phase rl (x)", "phase ap (y)", "phase fh (z)",
                              "through-plane phase"};
  Flow4D out;
  std::vector<int> present{0};
  if (!roles[4].empty()) {
    for (int r = 1; r < 4; ++r)
      if (!roles[r].empty())
        input_error("'{}': a through-plane phase series (its SequenceName or SeriesDescription "
                    "ends in 'in' or 'through') beside a {} series. A 2D phase-contrast folder "
                    "holds the magnitude and the through-plane phase alone; 4D flow is read as "
                    "rl, ap and fh components (a 4D series encoding the slab's normal as 'in' "
                    "is not mapped to one of them): one scan per folder",
                    dir.string(), role_names[r]);
    out.encoding = Encoding::through_plane;
    present.push_back(4);
  } else if (!roles[1].empty() || !roles[2].empty() || !roles[3].empty()) {
    present.insert(present.end(), {1, 2, 3});
  } else {
    out.encoding = Encoding::magnitude;
  }
  std::vector<Series> series;
  for (int r : present) {
    if (roles[r].empty())
      input_error("'{}': no {} series; 4D flow needs one magnitude series (ImageType M) and three "
                  "phase series (ImageType P) whose SequenceName or SeriesDescription ends in "
                  "rl, ap and fh; 2D phase contrast a magnitude and one through-plane phase "
                  "series; cine a magnitude series",
                  dir.string(), role_names[r]);
    if (roles[r].size() > 1)
      input_error("'{}': {} {} series (SeriesInstanceUIDs); one of each is expected", dir.string(),
                  roles[r].size(), role_names[r]);
    series.push_back(organise(role_names[r], roles[r].begin()->second));
  }

  // One frame count, one grid, one slice count.
  const std::string where0 = fmt::format("'{}', {} series", dir.string(), role_names[0]);
  const ImageGrid grid = frame_grid(series[0].frames[0], where0);
  if (out.encoding == Encoding::magnitude && grid.size[2] != 1)
    input_error("'{}': a magnitude series alone, {} slices per frame: the phase series are "
                "missing. 4D flow needs three phase series (ImageType P) whose SequenceName or "
                "SeriesDescription ends in rl, ap and fh beside the magnitude; a cine scan "
                "(magnitude only) is one slice",
                dir.string(), grid.size[2]);
  if (out.encoding != Encoding::velocity_3d && grid.size[2] != 1)
    input_error("'{}': {} with {} slices per frame; a 2D scan (phase contrast or cine) is one "
                "slice: give each slice's folder on its own",
                dir.string(), encoding_name(out.encoding), grid.size[2]);
  for (std::size_t r = 0; r < series.size(); ++r) {
    const char* name = role_names[present[r]];
    if (series[r].frames.size() != series[0].frames.size())
      input_error("'{}': the {} series has {} frames (trigger times), the magnitude {}; every "
                  "series must hold the same frames",
                  dir.string(), name, series[r].frames.size(), series[0].frames.size());
    for (std::size_t f = 0; f < series[r].frames.size(); ++f) {
      const std::string where = fmt::format("'{}', {} series, frame {} ({} ms)", dir.string(), name,
                                            f, series[r].times_ms[f]);
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

  // Venc and the phase-to-velocity mapping per phase series.
  out.grid = grid;
  out.period = series[0].frames[0][0]->nominal_interval_ms * 1e-3;
  std::vector<std::optional<double>> venc(series.size());
  std::vector<double> velocity_unit(series.size()); // rescaled-to-velocity: m/s per unit, else 0
  for (std::size_t r = 1; r < series.size(); ++r) {
    const SliceFile& f = *series[r].frames[0][0];
    venc[r] = options.venc > 0 ? std::optional<double>(options.venc) : f.venc;
    if (f.rescale_type == "cm/s" || f.rescale_type == "cm/sec")
      velocity_unit[r] = 1e-2;
    else if (f.rescale_type == "mm/s")
      velocity_unit[r] = 1e-3;
    else if (f.rescale_type == "m/s")
      velocity_unit[r] = 1.0;
    if (velocity_unit[r] == 0 && !venc[r])
      input_error("'{}', {} series (SequenceName '{}'): no venc. Classic phase images need it "
                  "from the SequenceName ('..._v<cm/s><dir>'), GE's (0019,10cc), Philips' "
                  "(2001,101a) or (0018,9217), or from --venc; images rescaled to velocity need "
                  "RescaleType 'cm/s', 'mm/s' or 'm/s'",
                  dir.string(), role_names[present[r]], f.sequence);
    if (venc[r])
      out.venc = std::max(out.venc, *venc[r]);
  }
  const std::size_t per_slice = std::size_t(grid.size[0]) * grid.size[1];
  std::vector<float> along(per_slice); // one phase image as velocity [m/s]
  for (std::size_t f = 0; f < series[0].frames.size(); ++f) {
    Frame fr;
    fr.time = series[0].times_ms[f] * 1e-3;
    fr.magnitude.resize(grid.count());
    for (auto& v : fr.velocity)
      v.assign(grid.count(), 0.0f);
    for (int k = 0; k < grid.size[2]; ++k) {
      const float* px = series[0].frames[f][k]->image->GetBufferPointer();
      std::copy(px, px + per_slice, fr.magnitude.data() + grid.linear(0, 0, k));
    }
    for (std::size_t r = 1; r < series.size(); ++r)
      for (int k = 0; k < grid.size[2]; ++k) {
        const SliceFile& sf = *series[r].frames[f][k];
        const float* px = sf.image->GetBufferPointer();
        if (velocity_unit[r] > 0) {
          for (std::size_t p = 0; p < per_slice; ++p)
            along[p] = static_cast<float>(px[p] * velocity_unit[r]);
        } else if (sf.intercept < 0) { // x in [-|b|, |b|)
          const double scale = *venc[r] / -sf.intercept;
          for (std::size_t p = 0; p < per_slice; ++p)
            along[p] = static_cast<float>(px[p] * scale);
        } else { // x in [0, 2^bits)
          const double half = std::ldexp(1.0, sf.bits_stored - 1);
          for (std::size_t p = 0; p < per_slice; ++p)
            along[p] = static_cast<float>((px[p] - half) / half * *venc[r]);
        }
        // 4D flow: the component itself; through-plane: v_n n (flow_dataset.hpp).
        const std::size_t offset = grid.linear(0, 0, k);
        for (int c = 0; c < 3; ++c) {
          const double share = present[r] == 4 ? grid.direction[2][c] : (present[r] == c + 1);
          if (share == 0.0)
            continue;
          float* dst = fr.velocity[c].data() + offset;
          for (std::size_t p = 0; p < per_slice; ++p)
            dst[p] = static_cast<float>(along[p] * share);
        }
      }
    out.frames.push_back(std::move(fr));
  }
  if (out.frames.size() > 1)
    out.frame_window = (out.frames.back().time - out.frames.front().time) / (out.frames.size() - 1);
  // Each image's source for messages: its series and the folder of its first file. Then the
  // values that are not numbers (rescaled pixels can be: a float pixel format, a rescale
  // slope that is not a number), counted as the volumes' are.
  for (std::size_t r = 0; r < series.size(); ++r) {
    const std::string source =
        fmt::format("'{}', {} series", series[r].frames[0][0]->file.parent_path().string(),
                    role_names[present[r]]);
    if (present[r] == 4)
      out.sources[1] = source;
    else
      out.sources[static_cast<std::size_t>(present[r])] = source;
  }
  out.check(dir.string());
  out.non_finite = survey_non_finite(out, fmt::format("'{}'", dir.string()));
  return out;
}

} // namespace tearflow::mri
