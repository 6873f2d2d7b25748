#include "x_display.h"

#include <X11/Xlib.h>
#include <vtkRenderWindow.h>

#include <cstdlib>

namespace sl {

namespace {

// The process's connection: opened once, never closed (the process's exit closes it, after the
// last window is gone).
struct XConnection {
  Display *display = nullptr;
  std::string error;
  XConnection()
  {
    const char *name = std::getenv("DISPLAY");
    if (!name || !*name) {
      error = "no X display for VTK's window: run under 'xvfb-run -a'";
      return;
    }
    display = XOpenDisplay(nullptr);
    if (!display) error = std::string("cannot connect to the X display '") + name + "'";
  }
};

XConnection &connection()
{
  static XConnection c;  // thread-safe initialization; windows are made on the main thread
  return c;
}

}  // namespace

bool open_x_display(std::string *error)
{
  XConnection &c = connection();
  if (!c.display && error) *error = c.error;
  return c.display != nullptr;
}

void attach_x_display(vtkRenderWindow *window)
{
  XConnection &c = connection();
  if (c.display) window->SetDisplayId(c.display);
}

}  // namespace sl
