// 4D-flow data as 4D NIfTI or MetaImage volumes through ITK (image_io.hpp for the layout):
// magnitude, vx, vy, vz, each an image over (i, j, k, frame).
#include "mri/image_io.hpp"

#include "core/image_bytes.hpp"
#include "mri/non_finite.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkImageIOBase.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>

#include <zlib.h>

#include "core/error.hpp"

namespace tearflow::mri {

namespace fs = std::filesystem;
using Volume = itk::Image<float, 4>;

namespace {

const char* const kNames[] = {"magnitude", "vx", "vy", "vz"};
const char* const kExtensions[] = {".nii.gz", ".nii", ".mha", ".mhd"};

itk::ImageIOBase::Pointer io_for(const std::string& ext) {
  if (ext == ".mha" || ext == ".mhd")
    return itk::MetaImageIO::New().GetPointer();
  return itk::NiftiImageIO::New().GetPointer();
}

/// The file of component `name` in `dir`, or an empty path.
fs::path find_component(const fs::path& dir, const std::string& name, std::string* ext) {
  for (const char* e : kExtensions) {
    const fs::path p = dir / (name + e);
    if (fs::exists(p)) {
      if (ext)
        *ext = e;
      return p;
    }
  }
  return {};
}

} // namespace

void write_volumes(const Flow4D& data, const fs::path& dir, const std::string& ext) {
  data.check("write_volumes");
  data.require(Encoding::velocity_3d, fmt::format("write_volumes '{}' (2D scans are written as "
                                                  "DICOM)",
                                                  dir.string()));
  fs::create_directories(dir);
  const ImageGrid& g = data.grid;
  const std::size_t n = g.count();
  for (int s = 0; s < 4; ++s) {
    auto img = Volume::New();
    Volume::RegionType region;
    region.SetSize({static_cast<itk::SizeValueType>(g.size[0]),
                    static_cast<itk::SizeValueType>(g.size[1]),
                    static_cast<itk::SizeValueType>(g.size[2]),
                    static_cast<itk::SizeValueType>(data.frames.size())});
    img->SetRegions(region);
    img->Allocate();
    Volume::PointType origin;
    Volume::SpacingType spacing;
    Volume::DirectionType direction;
    direction.SetIdentity();
    for (int r = 0; r < 3; ++r) {
      origin[r] = g.origin[r] * 1e3; // mm, as ITK's readers and viewers expect
      spacing[r] = g.spacing[r] * 1e3;
      for (int a = 0; a < 3; ++a)
        direction(r, a) = g.direction[a][r];
    }
    origin[3] = data.frames.front().time;
    spacing[3] = data.frames.size() > 1 ? data.frames[1].time - data.frames[0].time
                                        : std::max(data.frame_window, 1e-3);
    img->SetOrigin(origin);
    img->SetSpacing(spacing);
    img->SetDirection(direction);
    float* px = img->GetBufferPointer();
    for (std::size_t f = 0; f < data.frames.size(); ++f) {
      const std::vector<float>& src =
          s == 0 ? data.frames[f].magnitude : data.frames[f].velocity[s - 1];
      std::copy(src.begin(), src.end(), px + f * n);
    }
    auto writer = itk::ImageFileWriter<Volume>::New();
    writer->SetImageIO(io_for(ext));
    writer->SetInput(img);
    writer->SetFileName((dir / (std::string(kNames[s]) + ext)).string());
    try {
      writer->Update();
    } catch (const itk::ExceptionObject& e) {
      input_error("cannot write '{}': {}", writer->GetFileName(), e.GetDescription());
    }
  }
}

Flow4D read_volumes(const fs::path& dir, const ReadOptions& options) {
  Flow4D out;
  out.venc = options.venc;
  std::vector<Volume::Pointer> images;
  fs::path first;
  for (int s = 0; s < 4; ++s) {
    std::string ext;
    const fs::path file = find_component(dir, kNames[s], &ext);
    if (file.empty())
      input_error("'{}': no {} volume; a volume folder holds magnitude, vx, vy and vz as "
                  ".nii.gz, .nii, .mha or .mhd (4D: i, j, k, frame; velocity in m/s along LPS)",
                  dir.string(), kNames[s]);
    // The header first: a file cut short is refused before ITK reads it (MetaImage's reader
    // would print its own anonymous complaint, NIfTI's none).
    const itk::ImageIOBase::Pointer io = io_for(ext);
    io->SetFileName(file.string());
    auto reader = itk::ImageFileReader<Volume>::New();
    reader->SetImageIO(io);
    reader->SetFileName(file.string());
    try {
      io->ReadImageInformation();
      check_image_complete(file, io->GetImageSizeInBytes());
      reader->Update();
    } catch (const itk::ExceptionObject& e) {
      input_error("'{}': cannot be read as a 4D image ({})", file.string(), e.GetDescription());
    }
    Volume::Pointer img = reader->GetOutput();
    // The NIfTI library read NaN and infinite values as 0: put them back, so that they are
    // counted and refused where measured (non_finite.hpp) instead of read as no velocity.
    if (ext == ".nii" || ext == ".nii.gz")
      restore_nifti_non_finite(file, img->GetBufferPointer(),
                               img->GetLargestPossibleRegion().GetNumberOfPixels());
    out.sources[static_cast<std::size_t>(s)] = fmt::format("'{}'", file.string());
    if (s == 0) {
      first = file;
    } else {
      const Volume* a = images[0].GetPointer();
      bool same =
          a->GetLargestPossibleRegion().GetSize() == img->GetLargestPossibleRegion().GetSize();
      for (int r = 0; r < 4 && same; ++r) {
        same = std::abs(a->GetOrigin()[r] - img->GetOrigin()[r]) < 1e-4 * a->GetSpacing()[r] &&
               std::abs(a->GetSpacing()[r] - img->GetSpacing()[r]) < 1e-6 * a->GetSpacing()[r];
        for (int c = 0; c < 4; ++c)
          same = same && std::abs(a->GetDirection()(r, c) - img->GetDirection()(r, c)) < 1e-5;
      }
      if (!same)
        input_error("'{}': its size, frames, origin, spacing or orientation differ from '{}'; "
                    "all four volumes must share one grid",
                    file.string(), first.string());
    }
    images.push_back(img);
  }
  const Volume* a = images[0].GetPointer();
  const auto size = a->GetLargestPossibleRegion().GetSize();
  ImageGrid& g = out.grid;
  g.size = {int(size[0]), int(size[1]), int(size[2])};
  for (int r = 0; r < 3; ++r) {
    g.origin[r] = a->GetOrigin()[r] * 1e-3;
    g.spacing[r] = a->GetSpacing()[r] * 1e-3;
    for (int c = 0; c < 3; ++c)
      g.direction[c][r] = a->GetDirection()(r, c);
  }
  const std::size_t n = g.count();
  for (std::size_t f = 0; f < size[3]; ++f) {
    Frame fr;
    fr.time = a->GetOrigin()[3] + f * a->GetSpacing()[3];
    for (int s = 0; s < 4; ++s) {
      const float* px = images[s]->GetBufferPointer() + f * n;
      (s == 0 ? fr.magnitude : fr.velocity[s - 1]).assign(px, px + n);
    }
    out.frames.push_back(std::move(fr));
  }
  out.frame_window = a->GetSpacing()[3];
  out.check(dir.string());
  // Values that are not numbers: counted here, reported by the commands, refused where a
  // measurement reads one (non_finite.hpp).
  out.non_finite = survey_non_finite(out, fmt::format("'{}'", dir.string()));
  return out;
}

Flow4D read_flow_data(const fs::path& path, const ReadOptions& options) {
  if (fs::is_directory(path) && !find_component(path, "magnitude", nullptr).empty())
    return read_volumes(path, options);
  return read_dicom(path, options);
}

} // namespace tearflow::mri
