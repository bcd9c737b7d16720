#pragma once
// A time-resolved 4D-flow MRI dataset, as every part of src/mri uses it: per cardiac frame a
// magnitude image and the three velocity components on one voxel grid placed in patient
// coordinates. Patient coordinates are DICOM's LPS (x towards the patient's left, y
// posterior, z head), in metres; velocities are the LPS components in m/s, whatever the
// scanner encoded (the readers convert). No ITK here: this header is included widely.
//
// Voxel (i, j, k) has its centre at  p = origin + sum_a index_a spacing_a direction[a],
// direction[a] the unit vector of index axis a (DICOM's row and column directions and the
// slice normal; ITK's direction matrix has them as columns).
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "core/image_grid.hpp"
#include "core/types.hpp"

namespace tearflow::mri {

// The voxel grid (core/image_grid.hpp), as the MRI code has always named it.
using ::tearflow::centred_grid;
using ::tearflow::ImageGrid;
using ::tearflow::rotation;

struct Frame {
  double time = 0.0;                          ///< after the trigger, the window's centre [s]
  std::vector<float> magnitude;               ///< signal [arbitrary units], per voxel
  std::array<std::vector<float>, 3> velocity; ///< LPS components [m/s], per voxel
};

/// What a series measures. The 2D scans of the reference study are this dataset with one
/// slice (grid.size[2] == 1), so that reading, noise, corrections and plane measurement are
/// the 4D path's own.
enum class Encoding {
  velocity_3d,   ///< 4D flow: three velocity components
  through_plane, ///< 2D phase contrast: velocity along the slice normal (grid.direction[2])
                 ///< only, stored as v_n n (so v . n is the measured value; the in-plane
                 ///< components were not measured, not zero)
  magnitude,     ///< cine: magnitude only (velocity kept as zeros)
};

/// "4D flow", "2D phase contrast", "cine": for messages.
const char* encoding_name(Encoding e);

/// Frame f's velocity at voxel v along the unit vector n (a 2D scan's measured v . n).
inline double along(const Frame& f, std::size_t v, const Vec3& n) {
  return f.velocity[0][v] * n[0] + f.velocity[1][v] * n[1] + f.velocity[2][v] * n[2];
}

/// How far off a 2D scan's slice a point may lie and still be the slice's: its thickness,
/// at least 5 mm.
inline double slice_reach(const ImageGrid& g) {
  return g.spacing[2] > 5e-3 ? g.spacing[2] : 5e-3;
}

/// The values of one image of a scan that are not numbers (NaN or infinite), counted when the
/// scan is read (mri/non_finite.hpp). The images: magnitude, then what the encoding measured
/// (vx, vy, vz; the through-plane value; none for cine).
struct NonFiniteImage {
  int image = 0;                          ///< 0 magnitude, 1..3 vx, vy, vz; 1 a 2D scan's v . n
  std::vector<std::size_t> per_frame;     ///< such values in each frame
  std::array<int, 3> lowest{}, highest{}; ///< the index box of the voxels holding one
  std::size_t total() const;
};

struct Flow4D {
  ImageGrid grid;
  Encoding encoding = Encoding::velocity_3d;
  double venc = 0.0;         ///< velocity encoding [m/s]: +-venc is the phase range; 0 unknown
  double frame_window = 0.0; ///< time each frame averages over [s]; 0 unknown
  double period = 0.0;       ///< the cardiac cycle (R-R interval) the frames span [s]; 0 unknown
  std::vector<Frame> frames; ///< in time order
  /// Where each image was read from, for messages (the file of a volume, the series of DICOM
  /// files), indexed as NonFiniteImage::image; empty for a scan made in memory.
  std::array<std::string, 4> sources;
  /// The images holding values that are not numbers, as read (none: empty).
  std::vector<NonFiniteImage> non_finite;
  /// InputError (naming `where`) for frames of the wrong size or out of time order, or a 2D
  /// encoding on more than one slice.
  void check(const std::string& where) const;
  /// InputError naming `where` and what it needs when the data is not `e`.
  void require(Encoding e, const std::string& where) const;
  /// The cardiac cycle the frames span [s]: `period` (the R-R interval) when known, else the
  /// frames times their spacing (retrospective gating spreads them over the whole interval).
  /// InputError naming `where` for one frame without a period, or frames spanning it.
  double cycle(const std::string& where) const;
  /// InputError naming `what` when `p` lies farther than max(slice thickness, 5 mm) off a 2D
  /// scan's slice (a point of another plane would be projected onto it silently).
  void check_in_slice(const Vec3& p, const std::string& what) const;
};

/// The eight voxels and weights of trilinear interpolation at a continuous index, found
/// once and applied to several fields (magnitude and the three components).
struct Trilinear {
  std::array<std::size_t, 8> voxel{};
  std::array<double, 8> weight{};
  /// False outside the hull of the voxel centres.
  bool locate(const ImageGrid& grid, const Vec3& index);
  /// A voxel of weight 0 is not read: a value that is not a number beside the point (in the
  /// next slice, when the point lies on a voxel plane) does not make the sample one.
  double operator()(const std::vector<float>& field) const {
    double v = 0.0;
    for (int c = 0; c < 8; ++c)
      if (weight[c] != 0.0)
        v += weight[c] * field[voxel[c]];
    return v;
  }
};

/// The phase wrap of a velocity: v mapped into [-venc, venc).
double wrap_velocity(double v, double venc);

} // namespace tearflow::mri
