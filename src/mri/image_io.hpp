#pragma once
// Reading and writing 4D-flow data (docs/mri.md, "Input"). ITK does the I/O (GDCM for DICOM,
// NIfTI, MetaImage); its headers stay inside dicom_io.cpp and volume_io.cpp.
//
// DICOM, classic MR images, one file per slice and frame, in four series told apart by
// ImageType (0008,0008): one magnitude (M) and three phase (P) series, the velocity component
// of each from the end of its SequenceName (0018,0024) or SeriesDescription (0008,103e):
// "rl" (patient x, + towards the left), "ap" (y, + posterior), "fh" (z, + head) - DICOM's
// LPS. Frames by TriggerTime (0018,1060); slices by ImagePositionPatient along the normal
// of ImageOrientationPatient. Phase pixels map to velocity in one of these conventions:
//   - classic phase: pixels (after RescaleSlope/Intercept) span -venc..+venc linearly:
//       v = x / |intercept| venc    when RescaleIntercept < 0 (x in [-2^b, 2^b), Siemens),
//       v = (x - 2^(b-1)) / 2^(b-1) venc  otherwise, b = BitsStored;
//     venc from the first of: SequenceName "..._v<venc in cm/s><dir>" (Siemens), GE's
//     (0019,10cc) [mm/s], Philips' (2001,101a) [cm/s], the enhanced-MR attribute Velocity
//     Encoding Maximum Value (0018,9217) [cm/s] when a classic file carries it, or --venc;
//   - rescaled to velocity: RescaleType (0028,1054) "cm/s", "mm/s" or "m/s": the rescaled
//     pixel is the velocity in that unit (venc then optional, read as above when present).
// 2D scans, one slice per frame: 2D phase contrast (the magnitude and one phase series whose
// SequenceName or SeriesDescription ends in "in" or "through", as Siemens' fl2d1_v150in; the
// velocity along the slice normal row x column, whose sign the caller settles) and cine (a
// magnitude series alone); NominalInterval (0018,1062) gives the R-R interval when present.
// The enhanced MR multi-frame object (one file, per-frame functional groups with the MR
// Velocity Encoding Sequence) is not read: InputError says so.
//
// Volumes: a folder holding magnitude, vx, vy, vz as 4D NIfTI (.nii, .nii.gz) or MetaImage
// (.mha, .mhd) images: axes i, j, k, frame; spacing of the 4th axis the frame interval [s],
// its origin the first frame's time; velocity components along LPS in m/s (ITK converts
// NIfTI's RAS to LPS).
#include <filesystem>
#include <string>

#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

enum class PhaseConvention {
  classic,  ///< phase pixels over -venc..+venc, venc in the SequenceName (Siemens style)
  rescaled, ///< RescaleSlope/Intercept give the velocity in cm/s, RescaleType "cm/s"
};

struct DicomWriteOptions {
  PhaseConvention convention = PhaseConvention::classic;
  bool write_venc = true; ///< false: no venc anywhere (to test the reader's error)
  bool write_magnitude = true, write_vz = true; ///< false: to test missing series
};

/// Writes the series of `data`'s encoding under `dir` (one file per slice and frame): 4D flow
/// magnitude/, vx/, vy/, vz/; 2D phase contrast magnitude/, through/; cine magnitude/.
void write_dicom(const Flow4D& data, const std::filesystem::path& dir,
                 const DicomWriteOptions& options = {});

struct ReadOptions {
  double venc = 0.0; ///< [m/s]; > 0 overrides (or supplies) the files' venc
};

/// Reads every DICOM file under `dir` (recursively). InputError naming the folder or file
/// and what was expected: no magnitude or phase series for a component, series or frames
/// with different slice counts, positions, orientation or spacing, different frame counts,
/// no venc for classic phase.
Flow4D read_dicom(const std::filesystem::path& dir, const ReadOptions& options = {});

/// Writes magnitude, vx, vy, vz as 4D images with extension `ext` (".nii.gz", ".mha", ...);
/// 4D flow only (InputError for a 2D scan: those are written as DICOM).
void write_volumes(const Flow4D& data, const std::filesystem::path& dir,
                   const std::string& ext = ".nii.gz");

/// Reads a volume folder (above). InputError naming the file for a missing component or a
/// geometry or frame count that differs between them.
Flow4D read_volumes(const std::filesystem::path& dir, const ReadOptions& options = {});

/// A volume folder when `path` holds magnitude.(nii|nii.gz|mha|mhd), else DICOM.
Flow4D read_flow_data(const std::filesystem::path& path, const ReadOptions& options = {});

} // namespace tearflow::mri
