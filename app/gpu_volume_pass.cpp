#include "gpu_volume_pass.h"

#include <vtkObjectFactory.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLQuadHelper.h>
#include <vtkOpenGLRenderUtilities.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLShaderCache.h>
#include <vtkOpenGLState.h>
#include <vtkRenderState.h>
#include <vtkRenderer.h>
#include <vtkShaderProgram.h>
#include <vtkTextureObject.h>
#include <vtk_glew.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "sl_renderer_gpu.h"
#include "sl_shaders.h"
#include "sl_sky_sample.h"

namespace sl {

vtkStandardNewMacro(GpuVolumePass);

namespace {

constexpr int kMaxFields = SL_GPU_MAX_FIELDS; // two RGBA textures (shaders/volume_grid.glsl)
constexpr int kWavelengths = 3;

double seconds_since(std::chrono::steady_clock::time_point t)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// A fragment shader with the embedded texts where its markers stand: the shared per-sample
// physics and the lattice's look-ups (//SL::Physics), the shared physics alone (//SL::Model: the
// resolve reads no lattice), the shared sky, the view ray.
std::string with_shared(const char *shader)
{
  std::string s = shader;
  const auto put = [&s](const std::string &marker, const std::string &text) {
    const size_t at = s.find(marker);
    if (at != std::string::npos) s.replace(at, marker.size(), text);
  };
  put("//SL::Physics", gpu_physics_prelude() + sl_shader_volume_grid);
  put("//SL::Model", gpu_physics_prelude());
  put("//SL::Sky", gpu_sky_prelude());
  put("//SL::ViewRay", sl_shader_view_ray);
  return s;
}

void release(vtkTextureObject **t, vtkWindow *w)
{
  if (!*t) return;
  if (w) (*t)->ReleaseGraphicsResources(w);
  (*t)->Delete();
  *t = nullptr;
}

}  // namespace

std::string gpu_physics_prelude()
{
  return std::string("#define SL_MAX_FIELDS ") + std::to_string(kMaxFields) + "\n#define SL_MAX_WAVELENGTHS " +
         std::to_string(kWavelengths) + "\n" + sl_shader_volume_model + "\n" + sl_shader_sl_guards + "\n" +
         sl_shader_sl_sample_physics + "\n";
}

std::string gpu_sky_prelude()
{
  return "#define SL_SKY_REAL float\n#define SL_SKY_INFINITY slInfinity\n#define sl_sky_isinf(x) isinf(x)\n"
         "#define sl_sky_abs(x) abs(x)\n#define SL_SKY_IN_ARRAY(name, n) in float name[n]\n"
         "#define SL_SKY_OUT_ARRAY(name, n) out float name[n]\n#define SL_SUN_ANGULAR_DIAMETER_DEG " +
         std::to_string(SL_SUN_ANGULAR_DIAMETER_DEG) +
         "\nuniform float slInfinity; // GLSL 1.50 has no literal for it\n" + sl_shader_sky_sample_shared + "\n";
}

vtkTextureObject *new_float_texture(vtkOpenGLRenderWindow *win)
{
  vtkTextureObject *t = vtkTextureObject::New();
  t->SetContext(win);
  t->SetMinificationFilter(vtkTextureObject::Nearest);
  t->SetMagnificationFilter(vtkTextureObject::Nearest);
  t->SetWrapS(vtkTextureObject::ClampToEdge);
  t->SetWrapT(vtkTextureObject::ClampToEdge);
  t->SetWrapR(vtkTextureObject::ClampToEdge);
  return t;
}

bool ready_quad(vtkOpenGLQuadHelper **quad, vtkOpenGLRenderWindow *win, const std::string &fragment)
{
  if (!*quad)
    *quad = new vtkOpenGLQuadHelper(win, vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(),
                                    fragment.c_str(), "");
  else
    win->GetShaderCache()->ReadyShaderProgram((*quad)->Program);
  return (*quad)->Program && (*quad)->Program->GetCompiled();
}

bool bind_float_targets(vtkOpenGLFramebufferObject **fbo, vtkOpenGLRenderWindow *win, int w, int h, int targets)
{
  if (!*fbo) {
    *fbo = vtkOpenGLFramebufferObject::New();
    (*fbo)->SetContext(win);
  }
  if (!(*fbo)->PopulateFramebuffer(w, h, true, targets, VTK_FLOAT, false, 0, 0)) return false;
  (*fbo)->Bind();
  (*fbo)->ActivateDrawBuffers(targets);
  (*fbo)->ActivateReadBuffer(0);
  return true;
}

bool GpuModelTextures::Upload(vtkOpenGLRenderWindow *win, const sl_light_model *m, std::string *why)
{
  model_ = m;
  // ln-products and F_n: one row per (field, wavelength); Ams_n: the tables' rows stacked.
  int max_order = 1, rows = 0;
  angles_ = 2;
  angle_inv_step_ = 0.0;
  ams_row_.assign(kMaxFields * kWavelengths, 0);
  const bool tables = m->mode != SL_LIGHTING_LOW_ALBEDO && m->nf > 0;
  if (tables) {
    angles_ = m->table[0][0]->n_angles;
    angle_inv_step_ = m->table[0][0]->inv_step_rad;
    for (int j = 0; j < m->nf; ++j)
      for (int c = 0; c < kWavelengths; ++c) {
        max_order = std::max(max_order, m->max_order[j][c]);
        ams_row_[j * kWavelengths + c] = rows;
        rows += m->max_order[j][c] + 1;
      }
  }
  const int width = max_order + 1, height = kMaxFields * kWavelengths;
  std::vector<float> lp((size_t)width * height, 0.0f), fw((size_t)width * height, 0.0f);
  std::vector<float> ams((size_t)angles_ * std::max(rows, 1), 0.0f);
  if (tables)
    for (int j = 0; j < m->nf; ++j)
      for (int c = 0; c < kWavelengths; ++c) {
        const sl_phase_table *t = m->table[j][c];
        const int row = j * kWavelengths + c;
        for (int k = 0; k <= t->max_order; ++k) {
          lp[(size_t)row * width + k] = (float)m->log_product[j][c][k];
          fw[(size_t)row * width + k] = (float)t->forward[k];
        }
        std::copy(t->ams, t->ams + (size_t)(t->max_order + 1) * t->n_angles,
                  ams.begin() + (size_t)ams_row_[row] * angles_);
      }
  for (vtkTextureObject **t : {&log_product_, &forward_, &ams_})
    if (!*t) *t = new_float_texture(win);
  if (!log_product_->Create2DFromRaw(width, height, 1, VTK_FLOAT, lp.data()) ||
      !forward_->Create2DFromRaw(width, height, 1, VTK_FLOAT, fw.data()) ||
      !ams_->Create2DFromRaw(angles_, std::max(rows, 1), 1, VTK_FLOAT, ams.data())) {
    *why = "the OpenGL context cannot hold the particle tables as float textures";
    return false;
  }
  return true;
}

void GpuModelTextures::Activate()
{
  for (vtkTextureObject *t : {log_product_, forward_, ams_}) t->Activate();
}

void GpuModelTextures::Deactivate()
{
  for (vtkTextureObject *t : {log_product_, forward_, ams_}) t->Deactivate();
}

void GpuModelTextures::Release(vtkWindow *w)
{
  for (vtkTextureObject **t : {&log_product_, &forward_, &ams_}) release(t, w);
}

void GpuModelTextures::SetUniforms(vtkShaderProgram *p) const
{
  const sl_light_model *m = model_;
  float albedo_mean[kMaxFields] = {0}, albedo[kMaxFields * kWavelengths] = {0};
  int max_order[kMaxFields * kWavelengths] = {0};
  for (int j = 0; j < m->nf; ++j) {
    albedo_mean[j] = (float)m->albedo_mean[j];
    for (int c = 0; c < kWavelengths; ++c) {
      albedo[j * kWavelengths + c] = (float)m->albedo[j][c];
      max_order[j * kWavelengths + c] = m->max_order[j][c];
    }
  }
  p->SetUniformi("slNf", m->nf);
  p->SetUniformi("slMode", (int)m->mode);
  p->SetUniformf("slXi", (float)m->xi);
  p->SetUniform1fv("slAlbedoMean", kMaxFields, albedo_mean);
  p->SetUniform1fv("slAlbedo", kMaxFields * kWavelengths, albedo);
  p->SetUniform1iv("slMaxOrder", kMaxFields * kWavelengths, max_order);
  p->SetUniform1iv("slAmsRow", kMaxFields * kWavelengths, ams_row_.data());
  p->SetUniformi("slLogProduct", log_product_->GetTextureUnit());
  p->SetUniformi("slForward", forward_->GetTextureUnit());
  p->SetUniformi("slAms", ams_->GetTextureUnit());
}

GpuVolumePass::GpuVolumePass() = default;

GpuVolumePass::~GpuVolumePass() { ReleaseGraphicsResources(nullptr); }

void GpuVolumePass::SetRenderer(const sl_renderer *r)
{
  renderer_ = r;
  uploaded_ = swept_ = false;
}

std::string GpuVolumePass::Unsupported(const sl_renderer *r)
{
  sl_renderer_gpu_inputs in;
  sl_renderer_gpu_inputs_get(r, &in);
  const sl_light_model *m = in.model;
  if (m->nwl != kWavelengths)
    return "the GPU path carries three wavelengths; this scene has " + std::to_string(m->nwl);
  if (m->nf > kMaxFields) return "more than " + std::to_string(kMaxFields) + " particle fields";
  if (in.skylight && !in.sky_ready) return "the skylight's lattice was not built (sl_renderer_prepare_sky)";
  if (m->mode == SL_LIGHTING_LOW_ALBEDO) return "";
  const sl_phase_table *t0 = m->table[0][0];
  for (int j = 0; j < m->nf; ++j)
    for (int c = 0; c < m->nwl; ++c) {
      const sl_phase_table *t = m->table[j][c];
      if (t->n_angles != t0->n_angles || std::fabs(t->step_rad - t0->step_rad) > 1e-12)
        return "the particle tables use different angular grids";
    }
  return "";
}

bool GpuVolumePass::Fail(const std::string &why)
{
  error_ = why;
  ok_ = false;
  return false;
}

void GpuVolumePass::ReleaseGraphicsResources(vtkWindow *w)
{
  model_.Release(w);
  for (vtkTextureObject **t : {&fields_, &fields_hi_, &light_, &sunlight_, &opaque_, &sky_, &shadow_}) release(t, w);
  for (vtkOpenGLFramebufferObject **f : {&plane_fbo_, &eye_fbo_, &resolve_fbo_})
    if (*f) {
      if (w) (*f)->ReleaseGraphicsResources(w);
      (*f)->Delete();
      *f = nullptr;
    }
  delete sweep_quad_;
  delete eye_quad_;
  delete resolve_quad_;
  sweep_quad_ = eye_quad_ = resolve_quad_ = nullptr;
  uploaded_ = swept_ = false;
}

// The volume's fields and the model's tables, once per renderer.
bool GpuVolumePass::Upload(vtkOpenGLRenderWindow *win)
{
  sl_renderer_gpu_inputs in;
  sl_renderer_gpu_inputs_get(renderer_, &in);
  const sl_light_model *m = in.model;
  const size_t count = (size_t)in.n[0] * in.n[1] * in.n[2];
  // Fields: two float 3D textures, fields 0..3 and 4..7, a channel per present field (at least
  // one each: the second is a single zero texel where the scene has four fields or fewer).
  const int lo = std::min(std::max(1, m->nf), 4), hi = m->nf - 4;
  std::vector<float> fields(count * lo, 0.0f), fields_hi(hi > 0 ? count * hi : 1, 0.0f);
  for (size_t v = 0; v < (m->nf > 0 ? count : 0); ++v)
    for (int j = 0; j < m->nf; ++j) {
      const float beta = in.fields[v * m->nf + j];
      if (j < 4) fields[v * lo + j] = beta;
      else fields_hi[v * hi + (j - 4)] = beta;
    }
  if (!fields_) fields_ = new_float_texture(win);
  if (!fields_hi_) fields_hi_ = new_float_texture(win);
  if (!fields_->Create3DFromRaw(in.n[0], in.n[1], in.n[2], lo, VTK_FLOAT, fields.data()) ||
      !(hi > 0 ? fields_hi_->Create3DFromRaw(in.n[0], in.n[1], in.n[2], hi, VTK_FLOAT, fields_hi.data())
               : fields_hi_->Create3DFromRaw(1, 1, 1, 1, VTK_FLOAT, fields_hi.data())))
    return Fail("the OpenGL context cannot hold the volume as float 3D textures");
  std::string why;
  if (!model_.Upload(win, m, &why)) return Fail(why);
  uploaded_ = true;
  swept_ = false;
  return true;
}

// The lattice, the light volume's layout and the sun: what both shaders' look-ups need.
void GpuVolumePass::SetVolumeUniforms(vtkShaderProgram *p)
{
  sl_renderer_gpu_inputs in;
  sl_renderer_gpu_inputs_get(renderer_, &in);
  model_.SetUniforms(p);
  p->SetUniformi("slFields", fields_->GetTextureUnit());
  p->SetUniformi("slFieldsHi", fields_hi_->GetTextureUnit());
  p->SetUniformi("slLight", light_->GetTextureUnit());
  const float spacing[3] = {(float)in.spacing[0], (float)in.spacing[1], (float)in.spacing[2]};
  const float n[3] = {(float)in.n[0], (float)in.n[1], (float)in.n[2]};
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = -0.5f * spacing[a], hi[a] = (float)((in.n[a] - 0.5) * in.spacing[a]);
  p->SetUniform3f("slSpacing", spacing);
  p->SetUniform3f("slGridN", n);
  p->SetUniform3f("slBoxLo", lo);
  p->SetUniform3f("slBoxHi", hi);
  const sl_sweep_geometry &g = in.sweep;  // the CPU sweep's (sl_sweep_geometry.h)
  float e_axis[3] = {0, 0, 0}, e1[3] = {0, 0, 0}, e2[3] = {0, 0, 0};
  e_axis[g.axis] = e1[g.a1] = e2[g.a2] = 1.0f;
  p->SetUniform3f("slAxisE", e_axis);
  p->SetUniform3f("slA1E", e1);
  p->SetUniform3f("slA2E", e2);
  p->SetUniformf("slFirst", (float)g.first);
  p->SetUniformf("slStep", (float)g.step);
  const float sun[3] = {(float)in.sun_direction[0], (float)in.sun_direction[1], (float)in.sun_direction[2]};
  p->SetUniform3f("slSun", sun);
}

// The camera (shaders/view_ray.glsl): its basis (sl_camera_basis, as the CPU passes take it),
// the eye and the content box relative to the lattice's first sample.
void GpuVolumePass::SetViewUniforms(vtkShaderProgram *p)
{
  sl_renderer_gpu_inputs in;
  sl_renderer_gpu_inputs_get(renderer_, &in);
  const int width = camera_.width, height = camera_.height;
  double fwd[3], right[3], up[3];
  sl_camera_basis(&camera_, fwd, right, up);
  float eye[3], lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    eye[a] = (float)(camera_.position[a] - in.origin[a]);
    lo[a] = (float)(in.content_lo[a] - in.origin[a]);
    hi[a] = (float)(in.content_hi[a] - in.origin[a]);
  }
  p->SetUniform3f("slEye", eye);
  p->SetUniform3f("slFwd", fwd);
  p->SetUniform3f("slRight", right);
  p->SetUniform3f("slUp", up);
  p->SetUniformf("slTanHalf", (float)std::tan(0.5 * camera_.fov_deg * M_PI / 180.0));
  p->SetUniformf("slAspect", (float)width / height);
  const float size[2] = {(float)width, (float)height};
  p->SetUniform2f("slSize", size);
  p->SetUniform3f("slContentLo", lo);
  p->SetUniform3f("slContentHi", hi);
}

static void activate(std::initializer_list<vtkTextureObject *> ts)
{
  for (vtkTextureObject *t : ts) t->Activate();
}
static void deactivate(std::initializer_list<vtkTextureObject *> ts)
{
  for (vtkTextureObject *t : ts) t->Deactivate();
}

// The light volume: one plane per draw, copied into its layer of the 3D texture.
bool GpuVolumePass::Sweep(vtkOpenGLRenderWindow *win)
{
  sl_renderer_gpu_inputs in;
  sl_renderer_gpu_inputs_get(renderer_, &in);
  const sl_sweep_geometry &g = in.sweep;  // the CPU sweep's (sl_sweep_geometry.h)
  const int w = in.n[g.a1], h = in.n[g.a2], layers = in.n[g.axis];
  if (!light_) light_ = new_float_texture(win);
  if (!light_->Create3DFromRaw(w, h, layers, 4, VTK_FLOAT, nullptr))
    return Fail("the OpenGL context cannot hold the light volume as a float 3D texture");
  if (!bind_float_targets(&plane_fbo_, win, w, h, 1)) return Fail("the OpenGL context has no float render target");
  if (!ready_quad(&sweep_quad_, win, with_shared(sl_shader_volume_light_sweep)))
    return Fail("the light sweep's shader does not compile on this OpenGL context");
  vtkOpenGLState *gl = win->GetState();
  gl->vtkglViewport(0, 0, w, h);
  gl->vtkglScissor(0, 0, w, h);
  activate({fields_, fields_hi_, light_});
  model_.Activate();
  vtkShaderProgram *p = sweep_quad_->Program;
  SetVolumeUniforms(p);
  p->SetUniformf("slPath", (float)g.path);
  p->SetUniformf("slFirstPath", (float)g.first_path);
  const float shift[2] = {(float)g.shift[0], (float)g.shift[1]};
  p->SetUniform2f("slShift", shift);
  const float plane_n[2] = {(float)w, (float)h};
  p->SetUniform2f("slPlaneN", plane_n);
  for (int kk = 0; kk < layers; ++kk) {
    p->SetUniformi("slLayer", kk);
    p->SetUniformf("slPlaneK", (float)(g.first + kk * g.step));
    sweep_quad_->Render();
    light_->Bind();
    glCopyTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, kk, 0, 0, w, h);
  }
  model_.Deactivate();
  deactivate({fields_, fields_hi_, light_});
  // The skylight's lattice (render/volume/sky_light.h), built on the CPU for this sun: beta M per
  // wavelength and beta per sample; one zero texel without it, so the sampler stays valid.
  const bool sky = in.skylight && in.sky;
  const float zero[4] = {0, 0, 0, 0};
  if (!sky_) sky_ = new_float_texture(win);
  if (!(sky ? sky_->Create3DFromRaw(in.sky_n[0], in.sky_n[1], in.sky_n[2], 4, VTK_FLOAT, const_cast<float *>(in.sky))
            : sky_->Create3DFromRaw(1, 1, 1, 4, VTK_FLOAT, const_cast<float *>(zero))))
    return Fail("the OpenGL context cannot hold the skylight's lattice as a float 3D texture");
  swept_ = true;
  return true;
}

bool GpuVolumePass::Eye(vtkOpenGLRenderWindow *win)
{
  sl_renderer_gpu_inputs in;
  sl_renderer_gpu_inputs_get(renderer_, &in);
  const int width = camera_.width, height = camera_.height;
  // Sunlight through the air for this camera.
  std::vector<double> rows((size_t)SL_SUNLIGHT_TABLE_SIZE * kWavelengths);
  double z0 = 0.0, dz = 0.0, ground_radius = 0.0;
  int night = 0;
  sl_error err{};
  if (sl_renderer_sunlight_table(renderer_, &camera_, rows.data(), &z0, &dz, &ground_radius, &night, &err))
    return Fail(err.message);
  std::vector<float> rowsf(rows.begin(), rows.end());
  if (!sunlight_) sunlight_ = new_float_texture(win);
  if (!sunlight_->Create2DFromRaw(SL_SUNLIGHT_TABLE_SIZE, 1, kWavelengths, VTK_FLOAT, rowsf.data()))
    return Fail("the OpenGL context cannot hold the sunlight table");
  // Where each pixel's ray meets the terrain or the round earth (sl_camera.opaque_distance, rows
  // from the top): the eye pass stops there, as the CPU's does.
  std::vector<float> opaque((size_t)width * height, 3.0e38f);
  if (camera_.opaque_distance)
    for (size_t q = 0; q < opaque.size(); ++q) opaque[q] = std::fmin(camera_.opaque_distance[q], 3.0e38f);
  if (!opaque_) opaque_ = new_float_texture(win);
  if (!opaque_->Create2DFromRaw(width, height, 1, VTK_FLOAT, opaque.data()))
    return Fail("the OpenGL context cannot hold the opaque distances");
  if (!bind_float_targets(&eye_fbo_, win, width, height, 2)) return Fail("the OpenGL context has no float render targets");
  if (!ready_quad(&eye_quad_, win, with_shared(sl_shader_volume_eye)))
    return Fail("the eye pass's shader does not compile on this OpenGL context");
  vtkOpenGLState *gl = win->GetState();
  gl->vtkglViewport(0, 0, width, height);
  gl->vtkglScissor(0, 0, width, height);
  activate({fields_, fields_hi_, light_, sunlight_, opaque_, sky_});
  model_.Activate();
  vtkShaderProgram *p = eye_quad_->Program;
  p->SetUniformi("slSkylight", in.skylight && in.sky ? 1 : 0);
  p->SetUniformi("slSky", sky_->GetTextureUnit());
  {
    float o[3], h[3], n[3];
    for (int a = 0; a < 3; ++a) {
      o[a] = (float)(in.sky_origin[a] - in.origin[a]);  // relative to the lattice's first sample
      h[a] = (float)in.sky_spacing[a];
      n[a] = (float)in.sky_n[a];
    }
    p->SetUniform3f("slSkyOrigin", o);
    p->SetUniform3f("slSkySpacing", h);
    p->SetUniform3f("slSkyN", n);
  }
  SetVolumeUniforms(p);
  SetViewUniforms(p);
  p->SetUniformf("slAngleInvStep", (float)model_.AngleInvStep());
  p->SetUniformi("slAngles", model_.Angles());
  p->SetUniformi("slSunlight", sunlight_->GetTextureUnit());
  p->SetUniformi("slOpaque", opaque_->GetTextureUnit());
  p->SetUniformf("slSunZ0", (float)z0);
  p->SetUniformf("slSunDz", (float)dz);
  const float origin[3] = {(float)in.origin[0], (float)in.origin[1], (float)in.origin[2]};
  p->SetUniform3f("slOrigin", origin);
  p->SetUniformf("slGroundRadius", (float)ground_radius);
  p->SetUniformf("slTermination", (float)in.termination_transparency);
  p->SetUniformf("slMarchSamples", (float)in.march_samples);
  eye_quad_->Render();
  model_.Deactivate();
  deactivate({fields_, fields_hi_, light_, sunlight_, opaque_, sky_});
  glFinish();  // the eye pass's time is its own, not the read-back's or the resolve's
  if (!read_accumulator_) return true;
  const auto t = std::chrono::steady_clock::now();
  // Read the accumulator back: radiance and transparency, then the depth numerator.
  std::vector<float> color((size_t)width * height * 4), depth((size_t)width * height * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  eye_fbo_->ActivateReadBuffer(0);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, color.data());
  eye_fbo_->ActivateReadBuffer(1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, depth.data());
  const int stride = kWavelengths + 2;
  accumulator_.assign((size_t)width * height * stride, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t src = (size_t)(height - 1 - y) * width + x, dst = ((size_t)y * width + x) * stride;
      for (int c = 0; c < 4; ++c) accumulator_[dst + c] = color[4 * src + c];
      accumulator_[dst + 4] = depth[4 * src];
    }
  accumulator_read_seconds_ = seconds_since(t);
  return true;
}

// The layers from the eye accumulator (shaders/volume_resolve.glsl), read back into the images.
bool GpuVolumePass::Resolve(vtkOpenGLRenderWindow *win)
{
  const int width = camera_.width, height = camera_.height;
  if (volume_->width != width || volume_->height != height ||
      (background_ && (background_->width != width || background_->height != height)))
    return Fail("resolve: the images are not the camera's size");
  sl_renderer_gpu_sky sky;
  sl_error err{};
  if (sl_renderer_gpu_sky_get(renderer_, &camera_, &sky, &err)) return Fail(err.message);
  vtkTextureObject *color = eye_fbo_->GetColorAttachmentAsTextureObject(0);
  vtkTextureObject *depth = eye_fbo_->GetColorAttachmentAsTextureObject(1);
  if (!color || !depth) return Fail("the eye pass's targets cannot be read as textures");
  if (!bind_float_targets(&resolve_fbo_, win, width, height, 3))
    return Fail("the OpenGL context has no float render targets");
  if (!ready_quad(&resolve_quad_, win, with_shared(sl_shader_volume_resolve)))
    return Fail("the resolve's shader does not compile on this OpenGL context");
  vtkOpenGLState *gl = win->GetState();
  gl->vtkglViewport(0, 0, width, height);
  gl->vtkglScissor(0, 0, width, height);
  activate({color, depth});
  vtkShaderProgram *p = resolve_quad_->Program;
  SetViewUniforms(p);
  p->SetUniformi("slAccColor", color->GetTextureUnit());
  p->SetUniformi("slAccDepth", depth->GetTextureUnit());
  p->SetUniformf("slInfinity", std::numeric_limits<float>::infinity());
  p->SetUniformf("slMidDistance", (float)sky.mid_distance);
  float to_rgb[3][3];
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < kWavelengths; ++i) to_rgb[c][i] = (float)sky.to_rgb[c * sky.nwl + i];
  p->SetUniform3fv("slToRgb", 3, to_rgb);
  p->SetUniformi("slHaveAir", sky.has_atmosphere);
  p->SetUniform3f("slSkyRadiance", sky.sky_radiance);
  p->SetUniformf("slEyeAltitude", (float)sky.altitude);
  p->SetUniformf("slAirmass", (float)sky.airmass);  // infinite at night: the shared sky's encoding
  p->SetUniformf("slInvScaleHeight", (float)sky.inv_scale_height);
  p->SetUniformf("slGroundRadius", (float)sky.ground_radius);
  p->SetUniform3f("slVertical", sky.up);
  p->SetUniform3f("slSkySun", sky.sun);
  p->SetUniform3f("slBeta", sky.beta_sea_level);
  p->SetUniform3f("slIrradiance", sky.sun_irradiance);
  // The lit ground (render/volume/ground_shadow.h): its shadow map, one texel of 1 without it.
  {
    sl_renderer_gpu_inputs in;
    sl_renderer_gpu_inputs_get(renderer_, &in);
    const float one = 1.0f;
    if (!shadow_) shadow_ = new_float_texture(win);
    if (!(sky.ground_on ? shadow_->Create2DFromRaw(sky.shadow_n[0], sky.shadow_n[1], 1, VTK_FLOAT,
                                                   const_cast<float *>(sky.shadow))
                        : shadow_->Create2DFromRaw(1, 1, 1, VTK_FLOAT, const_cast<float *>(&one))))
      return Fail("the OpenGL context cannot hold the ground's shadow map");
    shadow_->Activate();
    float gs[3], gk[3], o[2], h[2], n[2];
    for (int c = 0; c < 3; ++c) gs[c] = (float)sky.ground_sun[c], gk[c] = (float)sky.ground_sky[c];
    for (int a = 0; a < 2; ++a) {
      o[a] = (float)(sky.shadow_origin[a] - in.origin[a]);  // relative to the lattice's first sample, as slEye
      h[a] = sky.ground_on ? (float)sky.shadow_spacing[a] : 1.0f;
      n[a] = sky.ground_on ? (float)sky.shadow_n[a] : 1.0f;
    }
    p->SetUniformi("slGroundOn", sky.ground_on);
    p->SetUniform3f("slGroundSun", gs);
    p->SetUniform3f("slGroundSky", gk);
    p->SetUniformi("slShadow", shadow_->GetTextureUnit());
    p->SetUniform2f("slShadowOrigin", o);
    p->SetUniform2f("slShadowSpacing", h);
    p->SetUniform2f("slShadowN", n);
  }
  resolve_quad_->Render();
  shadow_->Deactivate();
  deactivate({color, depth});
  glFinish();
  const auto t = std::chrono::steady_clock::now();
  // GL's rows from the bottom hold the image's rows from the top: read straight into the images.
  const size_t np = (size_t)width * height;
  std::vector<float> scalars(4 * np);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  resolve_fbo_->ActivateReadBuffer(0);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, volume_->rgba);
  resolve_fbo_->ActivateReadBuffer(1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, scalars.data());
  for (size_t q = 0; q < np; ++q) volume_->transparency[q] = scalars[4 * q], volume_->depth[q] = scalars[4 * q + 1];
  if (background_) {
    resolve_fbo_->ActivateReadBuffer(2);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, background_->rgba);
    for (size_t q = 0; q < np; ++q) background_->depth[q] = scalars[4 * q + 2], background_->transparency[q] = 0.0f;
  }
  layers_read_seconds_ = seconds_since(t);
  return true;
}

void GpuVolumePass::Render(const vtkRenderState *s)
{
  ok_ = false;
  error_.clear();
  this->NumberOfRenderedProps = 0;
  auto *win = vtkOpenGLRenderWindow::SafeDownCast(s->GetRenderer()->GetRenderWindow());
  if (!win || !renderer_ || camera_.width <= 0 || camera_.height <= 0) {
    Fail("no OpenGL render window, renderer or camera");
    return;
  }
  const std::string unsupported = Unsupported(renderer_);
  if (!unsupported.empty()) {
    Fail(unsupported);
    return;
  }
  vtkOpenGLState *gl = win->GetState();
  gl->PushFramebufferBindings();
  gl->vtkglDisable(GL_BLEND);
  gl->vtkglDisable(GL_DEPTH_TEST);
  bool good = true;
  if (!uploaded_) good = Upload(win);
  auto t = std::chrono::steady_clock::now();
  light_seconds_ = 0.0;
  if (good && !swept_) {
    good = Sweep(win);
    glFinish();
    light_seconds_ = seconds_since(t);
  }
  t = std::chrono::steady_clock::now();
  accumulator_read_seconds_ = 0.0;
  if (good) good = Eye(win);
  eye_seconds_ = seconds_since(t) - accumulator_read_seconds_;
  t = std::chrono::steady_clock::now();
  resolve_seconds_ = 0.0;
  if (good && volume_) {
    good = Resolve(win);
    resolve_seconds_ = seconds_since(t);
  }
  gl->PopFramebufferBindings();
  gl->vtkglEnable(GL_DEPTH_TEST);
  if (good && glGetError() != GL_NO_ERROR) good = Fail("OpenGL reported an error in the volume pass");
  ok_ = good;
}

}  // namespace sl
