// Writing what VTK drew (a chart's window, an assembled image) to PNG under a temporary name
// renamed when complete, like every other output of the project.
#pragma once

#include <string>

class vtkImageData;
class vtkRenderWindow;

namespace sl {

// Debian's VTK is GLX-only: without an X display a render window crashes instead of failing.
// Opens the process's X connection (x_display.h), which every later window shares; returns false
// with the one-line explanation when there is none or the server refuses.
bool have_display(std::string *error);

bool write_png(vtkImageData *image, const std::string &path, std::string *error);
bool write_window_png(vtkRenderWindow *window, const std::string &path, std::string *error);

}  // namespace sl
