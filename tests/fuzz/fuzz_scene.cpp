// libFuzzer target: the scene-file parser (JSON to render arguments) on arbitrary text.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const std::string text(reinterpret_cast<const char *>(data), size);
  std::vector<std::string> args;
  std::string error;
  sl::scene_text_to_arguments(text, "fuzz/scene.json", &args, &error);
  return 0;
}
