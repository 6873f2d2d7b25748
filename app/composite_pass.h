// A vtkRenderPass that composites Stormlight's HDR layers with VTK's own passes into a float
// framebuffer: the background (sky) behind VTK's opaque geometry, then the premultiplied volume
// layer at its depth. It owns its GL resources and computes no physics.
#pragma once

#include <vtkRenderPass.h>
#include <vtkSmartPointer.h>

#include <vector>

class vtkOpenGLFramebufferObject;
class vtkOpenGLQuadHelper;
class vtkTextureObject;

namespace sl {

class CompositePass : public vtkRenderPass {
 public:
  static CompositePass *New();
  vtkTypeMacro(CompositePass, vtkRenderPass);

  // Float RGBA rows from the top (premultiplied for the volume) and the volume's depth.
  void SetLayers(int width, int height, const float *background_rgba, const float *volume_rgba,
                 const float *volume_depth);
  // The pass that draws VTK's own props (opaque geometry, overlays).
  void SetDelegatePass(vtkRenderPass *pass);

  void Render(const vtkRenderState *s) override;
  void ReleaseGraphicsResources(vtkWindow *w) override;

  // The composited HDR frame read back from the float framebuffer, rows from the top.
  const std::vector<float> &Result() const { return result_; }
  bool Succeeded() const { return ok_; }

 protected:
  CompositePass();
  ~CompositePass() override;

 private:
  CompositePass(const CompositePass &) = delete;
  void operator=(const CompositePass &) = delete;

  int width_ = 0, height_ = 0;
  std::vector<float> background_, volume_, depth_;  // flipped to GL's bottom-up rows
  std::vector<float> result_;
  bool ok_ = false;
  vtkSmartPointer<vtkRenderPass> delegate_;
  vtkOpenGLFramebufferObject *fbo_ = nullptr;
  vtkTextureObject *background_tex_ = nullptr, *volume_tex_ = nullptr, *depth_tex_ = nullptr;
  vtkOpenGLQuadHelper *background_quad_ = nullptr, *volume_quad_ = nullptr;
};

}  // namespace sl
