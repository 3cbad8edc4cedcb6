// tear: reading a tearing strength map (`simulation.tearing.strength_map`, docs/simulation.md):
// a PNG, JPEG, TGA, BMP or other image stb_image decodes, as greyscale.
#pragma once

#include <string>

#include "tear/simulation_options.h"

namespace tear {

/// The largest strength map accepted, in texels (8192 × 8192).
constexpr long long max_strength_map_texels = 8192LL * 8192;

/// Reads the image `path` (already confined and checked by the caller) as greyscale in [0, 1]: 8-bit
/// images as value / 255, 16-bit ones as value / 65535, colour as its luma, alpha dropped. `file`
/// is the name the script gave, kept for messages. Throws an input `Error` naming `script` and
/// `key` for a file that is not an image stb_image reads, or one over `max_strength_map_texels`.
StrengthMap read_strength_map(const std::string& path, const std::string& file, const std::string& script,
                              const std::string& key);

}  // namespace tear
