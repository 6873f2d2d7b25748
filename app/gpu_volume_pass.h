// A vtkRenderPass that draws Stormlight's volume with the multiple-scattering lighting on the
// GPU: the light volume swept plane by plane along the sun's dominant axis into a float 3D
// texture (a sun change costs one sweep), then a ray-marched eye pass into float targets. The
// per-sample physics is render/volume/sl_sample_physics.h, the same text the CPU compiles. A
// resolve on the GPU then turns the eye accumulator into the frame's layers (the volume with the
// aerial perspective in front of it, the sky with the sun's disk behind), with the sky of
// render/sky/sky_sample_shared.h, also the CPU's text; the accumulator itself can be read back
// for the CPU's resolve. It owns its GL resources and defines no physics.
#pragma once

#include <vtkRenderPass.h>

#include <string>
#include <vector>

#include "sl_image.h"
#include "sl_renderer.h"

extern "C" {
#include "lighting.h"  // a C header without C++ guards
}

class vtkOpenGLFramebufferObject;
class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkShaderProgram;
class vtkTextureObject;
class vtkWindow;

namespace sl {

// The light model (render/volume/lighting.h) as the shaders read it: the ln-product and F_n
// rows and the stacked Ams_n tables in float textures, the albedos and orders in uniforms
// (shaders/volume_model.glsl names them).
class GpuModelTextures {
 public:
  ~GpuModelTextures() { Release(nullptr); }
  bool Upload(vtkOpenGLRenderWindow *win, const sl_light_model *m, std::string *why);
  void Activate();
  void Deactivate();
  void SetUniforms(vtkShaderProgram *p) const;  // after Activate
  void Release(vtkWindow *w);
  int Angles() const { return angles_; }
  double AngleInvStep() const { return angle_inv_step_; }

 private:
  const sl_light_model *model_ = nullptr;
  vtkTextureObject *log_product_ = nullptr, *forward_ = nullptr, *ams_ = nullptr;
  std::vector<int> ams_row_;
  int angles_ = 2;
  double angle_inv_step_ = 0.0;
};

// A full-screen quad running `fragment` (compiled on first use, readied afterwards); false when
// the context cannot compile it.
bool ready_quad(vtkOpenGLQuadHelper **quad, vtkOpenGLRenderWindow *win, const std::string &fragment);
// Binds *fbo (created on first use) with `targets` float RGBA colour targets of w x h for drawing.
bool bind_float_targets(vtkOpenGLFramebufferObject **fbo, vtkOpenGLRenderWindow *win, int w, int h, int targets);
// A float texture with nearest filtering and clamped edges (texelFetch reads it).
vtkTextureObject *new_float_texture(vtkOpenGLRenderWindow *win);

class GpuVolumePass : public vtkRenderPass {
 public:
  static GpuVolumePass *New();
  vtkTypeMacro(GpuVolumePass, vtkRenderPass);

  // The prepared CPU renderer whose volume, tables and sun the pass draws (not owned). Setting
  // it again (e.g. after a sun change) re-uploads and re-sweeps.
  void SetRenderer(const sl_renderer *r);
  void SetCamera(const sl_camera &cam) { camera_ = cam; }
  // Sweeps the light volume again on the next frame (what a sun change costs once the renderer
  // holds the new sun; used by the benchmark).
  void Resweep() { swept_ = false; }
  // Where the GPU resolve writes the frame's layers (allocated at the camera's size, not owned;
  // as sl_renderer_resolve_accumulator and sl_renderer_background write them); background may be
  // null. Without a volume layer the pass does not resolve.
  void SetLayers(sl_image *volume, sl_image *background) { volume_ = volume, background_ = background; }
  // Reads the raw eye accumulator back too (Accumulator(), for the CPU's resolve); off by default.
  void SetReadAccumulator(bool read) { read_accumulator_ = read; }

  void Render(const vtkRenderState *s) override;
  void ReleaseGraphicsResources(vtkWindow *w) override;

  // Rows from the top, nwl + 2 floats per pixel (sl_renderer_resolve_accumulator's layout).
  const std::vector<float> &Accumulator() const { return accumulator_; }
  bool Succeeded() const { return ok_; }
  const std::string &Error() const { return error_; }
  double LightSeconds() const { return light_seconds_; }
  double EyeSeconds() const { return eye_seconds_; }  // the eye pass's draw, finished
  double AccumulatorReadSeconds() const { return accumulator_read_seconds_; }  // 0 unless read back
  double ResolveSeconds() const { return resolve_seconds_; }  // the layers' read-back included
  double LayersReadSeconds() const { return layers_read_seconds_; }  // of which the read-back

  // Why this model cannot be drawn on the GPU (empty: it can): wavelengths other than three,
  // tables on different angular grids.
  static std::string Unsupported(const sl_renderer *r);

 protected:
  GpuVolumePass();
  ~GpuVolumePass() override;

 private:
  GpuVolumePass(const GpuVolumePass &) = delete;
  void operator=(const GpuVolumePass &) = delete;
  bool Upload(vtkOpenGLRenderWindow *win);
  bool Sweep(vtkOpenGLRenderWindow *win);
  bool Eye(vtkOpenGLRenderWindow *win);
  bool Resolve(vtkOpenGLRenderWindow *win);
  bool Fail(const std::string &why);
  void SetVolumeUniforms(vtkShaderProgram *p);
  void SetViewUniforms(vtkShaderProgram *p);

  const sl_renderer *renderer_ = nullptr;
  sl_camera camera_{};
  bool uploaded_ = false, swept_ = false, ok_ = false, read_accumulator_ = false;
  sl_image *volume_ = nullptr, *background_ = nullptr;
  std::string error_;
  std::vector<float> accumulator_;
  double light_seconds_ = 0.0, eye_seconds_ = 0.0, accumulator_read_seconds_ = 0.0, resolve_seconds_ = 0.0;
  double layers_read_seconds_ = 0.0;
  GpuModelTextures model_;
  vtkTextureObject *fields_ = nullptr, *fields_hi_ = nullptr; // fields 0..3 and 4..7
  vtkTextureObject *light_ = nullptr, *sunlight_ = nullptr;
  vtkTextureObject *opaque_ = nullptr;  // the camera's opaque distances (terrain, round earth)
  vtkTextureObject *sky_ = nullptr;     // the skylight's lattice, per sun
  vtkTextureObject *shadow_ = nullptr;  // the ground's shadow map, per sun
  vtkOpenGLFramebufferObject *plane_fbo_ = nullptr, *eye_fbo_ = nullptr, *resolve_fbo_ = nullptr;
  vtkOpenGLQuadHelper *sweep_quad_ = nullptr, *eye_quad_ = nullptr, *resolve_quad_ = nullptr;
};

// The GLSL text of the shared per-sample physics with the GPU model's accessors in front, as
// the pass compiles it (for tests that evaluate the shared functions on the GPU).
std::string gpu_physics_prelude();
// The GLSL text of the shared sky (render/sky/sky_sample_shared.h) in float, with its macros, the
// sun's angular diameter and the uniform slInfinity (a ray that meets no ground) in front.
std::string gpu_sky_prelude();

}  // namespace sl
