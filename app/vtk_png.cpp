#include "vtk_png.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkWindowToImageFilter.h>

#include <cstdio>
#include <cstdlib>

#include "sl_tempfile.h"
#include "x_display.h"

namespace sl {

bool have_display(std::string *error) { return open_x_display(error); }

bool write_png(vtkImageData *image, const std::string &path, std::string *error)
{
  char tmp[4096];
  sl_error err{};
  if (sl_temp_name(path.c_str(), tmp, sizeof tmp, &err)) {
    *error = err.message;
    return false;
  }
  // vtkPNGWriter needs the .png ending to be happy with the name; the rename drops it.
  const std::string tmp_png = std::string(tmp) + ".png";
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(tmp_png.c_str());
  writer->SetInputData(image);
  writer->Write();
  if (writer->GetErrorCode() != 0) {
    std::remove(tmp_png.c_str());
    *error = path + ": cannot write PNG";
    return false;
  }
  if (sl_temp_commit(tmp_png.c_str(), path.c_str(), &err)) {
    *error = err.message;
    return false;
  }
  return true;
}

bool write_window_png(vtkRenderWindow *window, const std::string &path, std::string *error)
{
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  return write_png(grab->GetOutput(), path, error);
}

}  // namespace sl
