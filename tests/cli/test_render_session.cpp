// A render session whose renderer was freed after its one frame (RenderSession::release_renderer,
// as `render` does before VTK's composite) refuses to draw or to change the light with a line,
// where it would otherwise read a null renderer.
#include <cstdio>
#include <memory>
#include <string>

#include "render_session.h"
extern "C" {
#include "sl_testing.h"
}

int main(int argc, char **argv)
{
  if (argc < 2) {
    std::fprintf(stderr, "usage: test_render_session DATASETS_DIR\n");
    return 2;
  }
  auto settings = std::make_unique<sl_settings>();
  sl_settings &s = *settings;
  sl_settings_defaults(&s);
  std::snprintf(s.data, sizeof s.data, "%s/cumulus.nc", argv[1]);
  s.width = 64, s.height = 48;
  sl_error err{};
  CHECK(sl_settings_check(&s, &err) == 0);
  sl::RenderSession session;
  std::string why;
  int exit_code = 0;
  CHECK(session.prepare(s, true, &why, &exit_code));
  if (!session.renderer) return sl_test_finish("render_session");
  session.release_renderer();
  CHECK(session.renderer == nullptr);

  // A camera the renderer would accept: only the guard stands between draw and a null renderer.
  sl_camera cam{};
  cam.width = 64, cam.height = 48, cam.fov_deg = 30.0;
  const double position[3] = {0.0, -50000.0, 2000.0}, target[3] = {0.0, 0.0, 1000.0}, up[3] = {0.0, 0.0, 1.0};
  for (int a = 0; a < 3; ++a) cam.position[a] = position[a], cam.target[a] = target[a], cam.up[a] = up[a];
  sl_image volume{}, background{};
  volume.width = background.width = cam.width, volume.height = background.height = cam.height;
  sl_render_stats stats{};
  bool gpu_done = true;
  std::string note;
  why.clear();
  CHECK(!session.draw(cam, false, &volume, &background, &stats, &gpu_done, &note, &why));
  CHECK(!gpu_done);
  CHECK(why.find("freed") != std::string::npos);
  why.clear();
  CHECK(!session.set_sun(30.0, 200.0, &why));
  CHECK(why.find("freed") != std::string::npos);
  why.clear();
  CHECK(!session.set_march_samples(2, &why));
  CHECK(why.find("freed") != std::string::npos);
  session.set_xi(0.1);
  CHECK(session.scene.xi == 0.1);
  return sl_test_finish("render_session");
}
