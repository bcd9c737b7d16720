#pragma once
// Image files cut short: ITK reads a NIfTI or MetaImage file that holds fewer bytes than its
// header announces without an error, the missing voxels left as they happen to be.
#include <cstdint>
#include <filesystem>

namespace tearflow {

/// InputError naming `file` when it holds fewer image bytes than `image_bytes` (from the
/// header, ITK's ImageIOBase::GetImageSizeInBytes) after its header: NIfTI (.nii, .nii.gz)
/// and MetaImage (.mha, or .mhd beside its data file). Other formats are not checked.
void check_image_complete(const std::filesystem::path& file, std::uint64_t image_bytes);

} // namespace tearflow
