#pragma once
#include <filesystem>

#include "tessera/image/exr.hpp"

namespace tessera {

// Denoises a finished render: reads `input` (an EXR with the beauty and the albedo, normal
// and variance AOVs), writes `output` with every input channel plus denoised.R/G/B, and,
// when `preview_png` is not empty, a PNG preview of the denoised beauty (`preview`: exposure
// and tone curve). The header's attributes (camera matrices, job, spp) are kept. `output` may be
// `input`. Throws std::runtime_error naming the missing channels or the unreadable file.
void denoise_exr_file(const std::filesystem::path& input, const std::filesystem::path& output,
                      const std::filesystem::path& preview_png, const PreviewOptions& preview = {});

}  // namespace tessera
