#pragma once
// Image files that ITK reads wrong without a word:
//  - cut short: a NIfTI or MetaImage file that holds fewer bytes than its header announces is
//    read without an error, the missing voxels left as they happen to be;
//  - NaN in NIfTI: the NIfTI library (nifti1_io's nifti_read_buffer) replaces every NaN and
//    infinite value of a float image with 0 as it loads it, so a masked or damaged region
//    reads as no signal or no velocity.
#include <cstdint>
#include <filesystem>

namespace tearflow {

/// InputError naming `file` when it holds fewer image bytes than `image_bytes` (from the
/// header, ITK's ImageIOBase::GetImageSizeInBytes) after its header: NIfTI (.nii, .nii.gz)
/// and MetaImage (.mha, or .mhd beside its data file). Other formats are not checked.
void check_image_complete(const std::filesystem::path& file, std::uint64_t image_bytes);

/// Puts the values that are not numbers (NaN, infinite) of the float NIfTI file `file` (.nii,
/// .nii.gz; float32 or float64 voxels) back into `pixels`, its first `count` voxels as ITK read
/// them (the file's order), where the NIfTI library made them 0; returns how many. Other
/// voxel types hold no such values: 0, the file unread.
std::uint64_t restore_nifti_non_finite(const std::filesystem::path& file, float* pixels,
                                       std::uint64_t count);

} // namespace tearflow
