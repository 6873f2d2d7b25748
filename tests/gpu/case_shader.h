// What the GPU physics tests share: the check that a shader's embedded copy is the source file,
// and a fragment shader run once per case over a row of cases (two RGBA float texels per case,
// the texture "cases"), writing RGBA float targets that are read back. Needs an X display.
#pragma once

#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLQuadHelper.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLState.h>
#include <vtkRenderWindow.h>
#include <vtkShaderProgram.h>
#include <vtkSmartPointer.h>
#include <vtkTextureObject.h>
#include <vtk_glew.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gpu_render.h"
#include "gpu_volume_pass.h"
#include "vtk_png.h"

namespace sl_test {

// Failed checks, counted; the first 20 printed with the case and the two values.
inline int &failures()
{
  static int count = 0;
  return count;
}
inline void check(bool ok, const char *what, int index, double got, double want)
{
  if (ok) return;
  if (++failures() <= 20) std::fprintf(stderr, "FAIL %s case %d: %.9g, expected %.9g\n", what, index, got, want);
}
inline bool close(double a, double b, double rel, double abs_tol)
{
  return std::isfinite(a) && std::fabs(a - b) <= rel * std::fabs(b) + abs_tol;
}

// Fixed-seed uniform numbers in [0, 1): the cases are the same on every run.
struct Lcg {
  unsigned long long s = 0x9e3779b97f4a7c15ull;
  double next()
  {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(s >> 11) / 9007199254740992.0;
  }
};

// The build embeds the file itself; a stale build is the only way for the two to differ.
inline bool embedded_text_is_file(const std::string &source_dir, const char *relative, const char *embedded)
{
  std::ifstream in(source_dir + "/" + relative, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  if (!in || ss.str() != embedded) {
    std::fprintf(stderr, "FAIL the shaders' copy of %s differs from the file (rebuild)\n", relative);
    return false;
  }
  std::printf("embedded %s: %zu bytes, identical to the file\n", relative, ss.str().size());
  return true;
}

class CaseShader {
 public:
  // A window of count x 1 pixels, the cases as a count x 2 texture, `targets` float targets and
  // the shader compiled; false with a one-line reason.
  bool init(int count, const std::vector<float> &cases, const std::string &shader, int targets, std::string *why)
  {
    count_ = count, targets_ = targets;
    if (!sl::have_display(why)) return false;
    window_ = sl::offscreen_window(count, 1);
    window_->Render();
    win_ = vtkOpenGLRenderWindow::SafeDownCast(window_);
    win_->MakeCurrent();
    input_ = sl::new_float_texture(win_);
    input_->Create2DFromRaw(count, 2, 4, VTK_FLOAT, const_cast<float *>(cases.data()));
    win_->GetState()->PushFramebufferBindings();
    pushed_ = true;
    if (!sl::bind_float_targets(&fbo_, win_, count, 1, targets) || !sl::ready_quad(&quad_, win_, shader)) {
      *why = "the OpenGL context cannot run the shader (float targets, GLSL)";
      return false;
    }
    win_->GetState()->vtkglViewport(0, 0, count, 1);
    win_->GetState()->vtkglDisable(GL_BLEND);
    win_->GetState()->vtkglDisable(GL_DEPTH_TEST);
    return true;
  }
  vtkOpenGLRenderWindow *window() const { return win_; }
  vtkShaderProgram *program() const { return quad_->Program; }
  // Draws every case and reads the targets back (out[t]: 4 floats per case); uniforms set on
  // program() before the call stay.
  void run(std::vector<float> *out)
  {
    input_->Activate();
    quad_->Program->SetUniformi("cases", input_->GetTextureUnit());
    quad_->Render();
    input_->Deactivate();
    for (int t = 0; t < targets_; ++t) {
      out[t].resize(4 * (size_t)count_);
      fbo_->ActivateReadBuffer(t);
      glReadPixels(0, 0, count_, 1, GL_RGBA, GL_FLOAT, out[t].data());
    }
  }
  ~CaseShader()
  {
    if (pushed_) win_->GetState()->PopFramebufferBindings();
    delete quad_;
    if (fbo_) fbo_->Delete();
    if (input_) input_->Delete();
  }

 private:
  int count_ = 0, targets_ = 0;
  bool pushed_ = false;
  vtkSmartPointer<vtkRenderWindow> window_;
  vtkOpenGLRenderWindow *win_ = nullptr;
  vtkTextureObject *input_ = nullptr;
  vtkOpenGLFramebufferObject *fbo_ = nullptr;
  vtkOpenGLQuadHelper *quad_ = nullptr;
};

}  // namespace sl_test
