// tests/phenomena/test_phenomena.c measured on GPU frames: its renderer call, drawn by the GPU pass.
#include <cstdio>
#include <string>

#include "gpu_render.h"

extern "C" int sl_test_gpu_render(const sl_renderer *r, const sl_camera *cam, sl_image *img)
{
  std::string why;
  if (!sl::gpu_render_volume(r, *cam, img, &why, nullptr)) {
    std::fprintf(stderr, "GPU path: %s\n", why.c_str());
    return 1;
  }
  return 0;
}
