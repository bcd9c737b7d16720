// Label maps through ITK: reading (any integer pixel type, cast to int16), writing, and the
// signed distance maps (Maurer's exact Euclidean transform, recursive Gaussian smoothing).
#include "geometry/label_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <string>

#include <boost/math/special_functions/erf.hpp>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkImageIOBase.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>
#include <itkNrrdImageIO.h>
#include <itkSignedMaurerDistanceMapImageFilter.h>
#include <itkSmoothingRecursiveGaussianImageFilter.h>

#include "core/error.hpp"
#include "core/image_bytes.hpp"

namespace tearflow::geometry {

namespace fs = std::filesystem;

namespace {

using LabelImage = itk::Image<std::int32_t, 3>;
using MaskImage = itk::Image<std::uint8_t, 3>;
using FloatImage = itk::Image<float, 3>;

template <typename Image> void place(Image* img, const ImageGrid& g) {
  typename Image::RegionType region;
  region.SetSize({static_cast<itk::SizeValueType>(g.size[0]),
                  static_cast<itk::SizeValueType>(g.size[1]),
                  static_cast<itk::SizeValueType>(g.size[2])});
  img->SetRegions(region);
  typename Image::PointType origin;
  typename Image::SpacingType spacing;
  typename Image::DirectionType direction;
  for (int r = 0; r < 3; ++r) {
    origin[r] = g.origin[r] * 1e3; // mm, as ITK's files and viewers have them
    spacing[r] = g.spacing[r] * 1e3;
    for (int a = 0; a < 3; ++a)
      direction(r, a) = g.direction[a][r];
  }
  img->SetOrigin(origin);
  img->SetSpacing(spacing);
  img->SetDirection(direction);
  img->Allocate();
}

// The reader for the file's extension (none for an unknown one). Chosen here, not by ITK's
// factory, whose registration this build does not generate.
itk::ImageIOBase::Pointer io_for(const fs::path& file) {
  std::string name = file.filename().string();
  std::transform(name.begin(), name.end(), name.begin(), ::tolower);
  auto ends = [&](const std::string& e) {
    return name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
  };
  if (ends(".nii") || ends(".nii.gz"))
    return itk::NiftiImageIO::New().GetPointer();
  if (ends(".mha") || ends(".mhd"))
    return itk::MetaImageIO::New().GetPointer();
  if (ends(".nrrd") || ends(".nhdr"))
    return itk::NrrdImageIO::New().GetPointer();
  return nullptr;
}

} // namespace

void check_label_map_name(const fs::path& file, const std::string& what) {
  if (!io_for(file))
    input_error("{} '{}': expected a .nii, .nii.gz, .mha, .mhd, .nrrd or .nhdr file", what,
                file.string());
}

LabelMap read_label_map(const fs::path& file) {
  const std::string src = "label map '" + file.string() + "'";
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    input_error("{}: no such file", src);
  itk::ImageIOBase::Pointer io = io_for(file);
  if (!io)
    input_error("{}: not an image ITK can read (expected NIfTI .nii/.nii.gz, MetaImage "
                ".mha/.mhd or NRRD .nrrd/.nhdr)",
                src);
  LabelImage::Pointer img;
  try {
    io->SetFileName(file.string());
    io->ReadImageInformation();
    if (io->GetNumberOfDimensions() != 3)
      input_error("{}: {} dimensions, expected a 3D label map", src, io->GetNumberOfDimensions());
    if (io->GetNumberOfComponents() != 1)
      input_error("{}: {} components per voxel, expected one label", src,
                  io->GetNumberOfComponents());
    const auto type = io->GetComponentType();
    if (type == itk::IOComponentEnum::FLOAT || type == itk::IOComponentEnum::DOUBLE)
      input_error("{}: floating-point voxels; a label map holds integer labels (a CT image "
                  "is not a segmentation)",
                  src);
    check_image_complete(file, io->GetImageSizeInBytes());
    auto reader = itk::ImageFileReader<LabelImage>::New();
    reader->SetImageIO(io);
    reader->SetFileName(file.string());
    reader->Update();
    img = reader->GetOutput();
  } catch (const itk::ExceptionObject& e) {
    input_error("{}: cannot be read ({})", src, e.GetDescription());
  }
  LabelMap out;
  out.file = file;
  const auto size = img->GetLargestPossibleRegion().GetSize();
  for (int a = 0; a < 3; ++a) {
    out.grid.size[a] = static_cast<int>(size[a]);
    out.grid.origin[a] = img->GetOrigin()[a] * 1e-3;
    out.grid.spacing[a] = img->GetSpacing()[a] * 1e-3;
    for (int r = 0; r < 3; ++r)
      out.grid.direction[a][r] = img->GetDirection()(r, a);
  }
  const std::int32_t* px = img->GetBufferPointer();
  out.labels.resize(out.grid.count());
  for (std::size_t i = 0; i < out.labels.size(); ++i) {
    if (px[i] < std::numeric_limits<std::int16_t>::min() ||
        px[i] > std::numeric_limits<std::int16_t>::max())
      input_error("{}: label {} beyond the range of labels read (-32768..32767)", src, px[i]);
    out.labels[i] = static_cast<std::int16_t>(px[i]);
  }
  return out;
}

void write_label_map(const LabelMap& map, const fs::path& file) {
  // Labels fit a byte in every map we write; the smaller file is what segmentation tools
  // write too.
  using ByteImage = itk::Image<std::uint8_t, 3>;
  auto bytes = ByteImage::New();
  place(bytes.GetPointer(), map.grid);
  for (std::size_t i = 0; i < map.labels.size(); ++i) {
    if (map.labels[i] < 0 || map.labels[i] > 255)
      input_error("write_label_map '{}': label {} does not fit a byte", file.string(),
                  map.labels[i]);
    bytes->GetBufferPointer()[i] = static_cast<std::uint8_t>(map.labels[i]);
  }
  auto writer = itk::ImageFileWriter<ByteImage>::New();
  check_label_map_name(file, "label map");
  writer->SetImageIO(io_for(file));
  writer->SetInput(bytes);
  writer->SetFileName(file.string());
  // NIfTI compresses by its name (.nii.gz); the others are told to: a label map is mostly
  // background and shrinks a hundredfold.
  writer->SetUseCompression(file.extension() != ".nii");
  try {
    writer->Update();
  } catch (const itk::ExceptionObject& e) {
    input_error("cannot write label map '{}': {}", file.string(), e.GetDescription());
  }
}

std::vector<float> signed_distance(const ImageGrid& grid, const std::vector<std::uint8_t>& mask,
                                   double sigma, bool curvature_corrected) {
  std::vector<float> out(grid.count(), std::numeric_limits<float>::max());
  if (std::none_of(mask.begin(), mask.end(), [](std::uint8_t m) { return m; }))
    return out; // no voxel of the set: everything is far outside
  auto img = MaskImage::New();
  place(img.GetPointer(), grid);
  std::copy(mask.begin(), mask.end(), img->GetBufferPointer());
  using Maurer = itk::SignedMaurerDistanceMapImageFilter<MaskImage, FloatImage>;
  auto maurer = Maurer::New();
  maurer->SetInput(img);
  maurer->SetUseImageSpacing(true);
  maurer->SetSquaredDistance(false);
  maurer->SetInsideIsPositive(false);
  maurer->SetBackgroundValue(0);
  maurer->Update();
  FloatImage::Pointer field = maurer->GetOutput();
  // In mm, ITK's units here: the zero on the set's boundary voxels moves to their faces.
  const double s = (grid.spacing[0] + grid.spacing[1] + grid.spacing[2]) / 3 * 1e3;
  float* f = field->GetBufferPointer();
  for (std::size_t i = 0; i < out.size(); ++i)
    f[i] = static_cast<float>(f[i] - 0.5 * s);
  using Gaussian = itk::SmoothingRecursiveGaussianImageFilter<FloatImage, FloatImage>;
  if (sigma > 0) {
    auto smooth = Gaussian::New();
    smooth->SetInput(field);
    smooth->SetSigma(sigma * 1e3);
    smooth->Update();
    field = smooth->GetOutput();
    f = field->GetBufferPointer();
  }
  // Maurer's distances are to voxel centres: half a voxel moves the zero to the faces of an
  // axis-aligned surface, but on an oblique one the nearest voxel centre lies almost on the
  // surface, and the faces' correction then shrinks the set by up to half a voxel (0.2 mm
  // of a 1 mm map's 2 mm flap). Within `reach` of the surface the distance is measured to
  // the surface itself instead: near it (|d| < 1.6 voxels) from the mask blurred by a
  // Gaussian of 0.8 voxels, whose 0.5 level is the surface (a plane's blurred step is
  // 0.5 erfc(d / (g sqrt 2)) whatever its orientation), which also gives each such voxel its
  // nearest surface point; then outwards, each voxel taking the nearest of its neighbours'
  // surface points (closest-point propagation, in order of distance).
  auto indicator = FloatImage::New();
  place(indicator.GetPointer(), grid);
  for (std::size_t i = 0; i < out.size(); ++i)
    indicator->GetBufferPointer()[i] = mask[i] ? 1.0f : 0.0f;
  const double g = 0.8 * s;
  auto blur = Gaussian::New();
  blur->SetInput(indicator);
  blur->SetSigma(g);
  blur->Update();
  const float* b = blur->GetOutput()->GetBufferPointer();
  const std::size_t nx = grid.size[0], nxy = nx * grid.size[1];
  const std::size_t step[3] = {1, nx, nxy};
  auto point = [&](std::size_t v) {
    return grid.point({double(v % nx), double((v / nx) % grid.size[1]), double(v / nxy)});
  };
  // The blurred mask's gradient at voxel v in world axes [1/m] (points inwards).
  auto gradient = [&](std::size_t v) {
    Vec3 grad{0, 0, 0};
    for (int a = 0; a < 3; ++a)
      grad = grad + ((b[v + step[a]] - b[v - step[a]]) / (2 * grid.spacing[a])) * grid.direction[a];
    return grad;
  };
  auto unit = [](const Vec3& x) {
    const double n = std::sqrt(dot(x, x));
    return n > 0 ? (1 / n) * x : Vec3{0, 0, 0};
  };
  // A curved surface's blurred step reaches 0.5 inside it: with X ~ N(0, g^2) in each
  // direction, the set x_n < d - (k1 x_1^2 + k2 x_2^2) / 2 has probability
  // Phi(d/g) - phi(d/g) (k1 + k2) g / 2 to first order, so the 0.5 level lies (k1 + k2) g^2 / 2
  // inside the surface (k > 0 convex; about 0.5 % of a 10 mm lumen's area at 1 mm voxels, 3 %
  // of a 5 mm wide true lumen's, and more at the corners where the flap meets the wall).
  // The sum of curvatures is -div n of the inward unit normal n, by central differences.
  const double g_m = g * 1e-3;
  auto curvature_shift = [&](std::size_t v) {
    double div = 0;
    for (int a = 0; a < 3; ++a)
      div += dot(unit(gradient(v + step[a])) - unit(gradient(v - step[a])), grid.direction[a]) /
             (2 * grid.spacing[a]);
    // Bounded by a blurred corner's (at most about 1.5 / g, the level's curvature there).
    return std::clamp(-div, -1.5 / g_m, 1.5 / g_m) * g_m * g_m / 2;
  };
  std::vector<Vec3> nearest(out.size());
  std::vector<double> dist(out.size(), std::numeric_limits<double>::infinity());
  std::vector<std::int8_t> side(curvature_corrected ? out.size() : 0, 0); // 0: the mask's
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
  for (int k = 2; k + 2 < grid.size[2]; ++k)
    for (int j = 2; j + 2 < grid.size[1]; ++j)
      for (int i = 2; i + 2 < grid.size[0]; ++i) {
        const std::size_t v = grid.linear(i, j, k);
        if (!(b[v] > 0.02f && b[v] < 0.98f))
          continue;
        double d = g * std::sqrt(2.0) * boost::math::erfc_inv(2.0 * b[v]) * 1e-3; // [m]
        const Vec3 grad = gradient(v);
        const double gn = std::sqrt(dot(grad, grad));
        if (gn <= 0)
          continue;
        if (curvature_corrected) {
          d -= curvature_shift(v);  // the surface lies that much beyond the 0.5 level
          side[v] = d < 0 ? -1 : 1; // the shift may carry a voxel across the surface
        }
        nearest[v] = point(v) + (d / gn) * grad; // grad points inwards
        dist[v] = std::abs(d);
        heap.push({dist[v], v});
      }
  const double reach = 6e-3;
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    if (d > dist[v])
      continue;
    grid.for_each_neighbour(v, [&](std::size_t u, int, int, int) {
      const Vec3 e = point(u) - nearest[v];
      const double du = std::sqrt(dot(e, e));
      if (du < dist[u] && du < reach) {
        dist[u] = du;
        nearest[u] = nearest[v];
        heap.push({du, u});
      }
    });
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(dist[i]))
      out[i] = static_cast<float>(f[i] * 1e-3);
    else if (!side.empty() && side[i] != 0)
      out[i] = static_cast<float>(side[i] * dist[i]);
    else
      out[i] = static_cast<float>(mask[i] ? -dist[i] : dist[i]);
  return out;
}

} // namespace tearflow::geometry
