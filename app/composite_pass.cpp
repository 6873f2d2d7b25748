#include "composite_pass.h"

#include <vtkCamera.h>
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

#include "sl_shaders.h"

namespace sl {

vtkStandardNewMacro(CompositePass);

CompositePass::CompositePass() = default;

CompositePass::~CompositePass()
{
  delete background_quad_;
  delete volume_quad_;
  if (fbo_) fbo_->Delete();
  if (background_tex_) background_tex_->Delete();
  if (volume_tex_) volume_tex_->Delete();
  if (depth_tex_) depth_tex_->Delete();
}

void CompositePass::SetDelegatePass(vtkRenderPass *pass) { delegate_ = pass; }

// OpenGL's rows run bottom-up; Stormlight's images top-down.
static std::vector<float> flip_rows(const float *src, int width, int height, int comps)
{
  std::vector<float> out((size_t)width * height * comps);
  const size_t row = (size_t)width * comps;
  for (int y = 0; y < height; ++y)
    std::copy(src + (size_t)y * row, src + (size_t)(y + 1) * row, out.begin() + (size_t)(height - 1 - y) * row);
  return out;
}

void CompositePass::SetLayers(int width, int height, const float *background_rgba, const float *volume_rgba,
                              const float *volume_depth)
{
  width_ = width;
  height_ = height;
  background_ = flip_rows(background_rgba, width, height, 4);
  volume_ = flip_rows(volume_rgba, width, height, 4);
  depth_ = flip_rows(volume_depth, width, height, 1);
}

void CompositePass::ReleaseGraphicsResources(vtkWindow *w)
{
  if (delegate_) delegate_->ReleaseGraphicsResources(w);
  delete background_quad_;
  delete volume_quad_;
  background_quad_ = volume_quad_ = nullptr;
  for (vtkTextureObject **t : {&background_tex_, &volume_tex_, &depth_tex_})
    if (*t) {
      (*t)->ReleaseGraphicsResources(w);
      (*t)->Delete();
      *t = nullptr;
    }
  if (fbo_) {
    fbo_->ReleaseGraphicsResources(w);
    fbo_->Delete();
    fbo_ = nullptr;
  }
}

static vtkTextureObject *upload(vtkOpenGLRenderWindow *win, vtkTextureObject *tex, int w, int h, int comps,
                                std::vector<float> &data)
{
  if (!tex) tex = vtkTextureObject::New();
  tex->SetContext(win);
  tex->SetMinificationFilter(vtkTextureObject::Nearest);
  tex->SetMagnificationFilter(vtkTextureObject::Nearest);
  tex->SetWrapS(vtkTextureObject::ClampToEdge);
  tex->SetWrapT(vtkTextureObject::ClampToEdge);
  tex->Create2DFromRaw(w, h, comps, VTK_FLOAT, data.data());
  return tex;
}

void CompositePass::Render(const vtkRenderState *s)
{
  ok_ = false;
  this->NumberOfRenderedProps = 0;
  vtkRenderer *ren = s->GetRenderer();
  auto *win = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!win || width_ <= 0 || height_ <= 0) return;
  vtkOpenGLState *gl = win->GetState();

  if (!fbo_) {
    fbo_ = vtkOpenGLFramebufferObject::New();
    fbo_->SetContext(win);
  }
  gl->PushFramebufferBindings();
  // One float colour target and a depth buffer: HDR from the first pass to the read-back.
  if (!fbo_->PopulateFramebuffer(width_, height_, true, 1, VTK_FLOAT, true, 32, 0)) {
    gl->PopFramebufferBindings();
    return;
  }
  fbo_->Bind();
  fbo_->ActivateDrawBuffer(0);
  gl->vtkglViewport(0, 0, width_, height_);
  gl->vtkglScissor(0, 0, width_, height_);
  gl->vtkglClearColor(0.0, 0.0, 0.0, 0.0);
  gl->vtkglClearDepth(1.0);
  gl->vtkglDepthMask(GL_TRUE);
  gl->vtkglClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // 1. VTK's own props (terrain, outlines) with depth.
  if (delegate_) {
    vtkRenderState s2(ren);
    s2.SetPropArrayAndCount(s->GetPropArray(), s->GetPropArrayCount());
    s2.SetFrameBuffer(fbo_);
    delegate_->Render(&s2);
    this->NumberOfRenderedProps += delegate_->GetNumberOfRenderedProps();
    fbo_->Bind();
    fbo_->ActivateDrawBuffer(0);
  }

  background_tex_ = upload(win, background_tex_, width_, height_, 4, background_);
  volume_tex_ = upload(win, volume_tex_, width_, height_, 4, volume_);
  depth_tex_ = upload(win, depth_tex_, width_, height_, 1, depth_);

  gl->vtkglViewport(0, 0, width_, height_);
  gl->vtkglEnable(GL_DEPTH_TEST);
  gl->vtkglDepthMask(GL_FALSE);

  // 2. The sky where nothing was drawn (depth still at the far plane).
  gl->vtkglDisable(GL_BLEND);
  gl->vtkglDepthFunc(GL_LEQUAL);
  if (!background_quad_)
    background_quad_ = new vtkOpenGLQuadHelper(win, vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(),
                                               sl_shader_composite_background, "");
  else
    win->GetShaderCache()->ReadyShaderProgram(background_quad_->Program);
  if (!background_quad_->Program || !background_quad_->Program->GetCompiled()) {
    gl->PopFramebufferBindings();
    return;
  }
  background_tex_->Activate();
  background_quad_->Program->SetUniformi("background", background_tex_->GetTextureUnit());
  background_quad_->Render();
  background_tex_->Deactivate();

  // 3. The volume, premultiplied "over", hidden where geometry is nearer.
  gl->vtkglEnable(GL_BLEND);
  gl->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  if (!volume_quad_)
    volume_quad_ = new vtkOpenGLQuadHelper(win, vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(),
                                           sl_shader_composite_volume, "");
  else
    win->GetShaderCache()->ReadyShaderProgram(volume_quad_->Program);
  if (!volume_quad_->Program || !volume_quad_->Program->GetCompiled()) {
    gl->PopFramebufferBindings();
    return;
  }
  double range[2];
  ren->GetActiveCamera()->GetClippingRange(range);
  volume_tex_->Activate();
  depth_tex_->Activate();
  volume_quad_->Program->SetUniformi("volumeColor", volume_tex_->GetTextureUnit());
  volume_quad_->Program->SetUniformi("volumeDepth", depth_tex_->GetTextureUnit());
  volume_quad_->Program->SetUniformf("nearPlane", (float)range[0]);
  volume_quad_->Program->SetUniformf("farPlane", (float)range[1]);
  volume_quad_->Render();
  volume_tex_->Deactivate();
  depth_tex_->Deactivate();
  gl->vtkglDisable(GL_BLEND);
  gl->vtkglDepthMask(GL_TRUE);

  // 4. Read the HDR result back.
  fbo_->ActivateReadBuffer(0);
  std::vector<float> pixels((size_t)width_ * height_ * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, pixels.data());
  result_ = flip_rows(pixels.data(), width_, height_, 4);
  gl->PopFramebufferBindings();
  ok_ = glGetError() == GL_NO_ERROR;
}

}  // namespace sl
