#include "io/image/read_strength_map.h"

#include <stb_image.h>

#include <algorithm>
#include <memory>

#include "tear/error.h"
#include "tear/input_file.h"

namespace tear {

StrengthMap read_strength_map(const std::string& path, const std::string& file, const std::string& script,
                              const std::string& key) {
  const std::string bytes = read_input_file(path, "the strength map");
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(std::min<std::size_t>(bytes.size(), 0x7fffffff));
  auto refuse = [&](const std::string& why) { return input_error(script, key + ": " + file + ": " + why); };
  if (bytes.size() > 0x7fffffff) throw refuse("the image is over 2 GiB");
  int width = 0, height = 0, channels = 0;
  // The size first, from the header: a small file may declare a huge image.
  if (!stbi_info_from_memory(data, size, &width, &height, &channels))
    throw refuse(std::string("not an image stb_image reads (") + stbi_failure_reason() + ")");
  if (width <= 0 || height <= 0 || static_cast<long long>(width) * height > max_strength_map_texels)
    throw refuse("the image is " + std::to_string(width) + " x " + std::to_string(height) + ", over the limit of " +
                 std::to_string(max_strength_map_texels) + " texels");
  StrengthMap map;
  map.file = file;
  map.width = width;
  map.height = height;
  const std::size_t texels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  map.value.resize(texels);
  int w = 0, h = 0, c = 0;
  if (stbi_is_16_bit_from_memory(data, size)) {
    std::unique_ptr<stbi_us, void (*)(void*)> grey(stbi_load_16_from_memory(data, size, &w, &h, &c, 1), stbi_image_free);
    if (!grey || w != width || h != height) throw refuse(std::string("cannot decode the image (") + stbi_failure_reason() + ")");
    for (std::size_t i = 0; i < texels; ++i) map.value[i] = static_cast<float>(grey.get()[i] / 65535.0);
  } else {
    std::unique_ptr<stbi_uc, void (*)(void*)> grey(stbi_load_from_memory(data, size, &w, &h, &c, 1), stbi_image_free);
    if (!grey || w != width || h != height) throw refuse(std::string("cannot decode the image (") + stbi_failure_reason() + ")");
    for (std::size_t i = 0; i < texels; ++i) map.value[i] = static_cast<float>(grey.get()[i] / 255.0);
  }
  return map;
}

}  // namespace tear
