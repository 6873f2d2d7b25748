// One X connection for the whole process, shared by every VTK window the app opens.
//
// Why: an X server resets when its last client disconnects, and a connection that arrives
// during the reset is refused. A process that closes one VTK window (each opens and closes its
// own connection) and opens the next one a moment later (render --gpu: the GPU pass's window,
// then the composite's) left the server without clients in between; measured under Xvfb, 7 % of
// immediate reconnects failed ("vtkXOpenGLRenderWindow: bad X server connection", and VTK
// aborts). With one connection held until exit the server never sees the process leave.
#pragma once

#include <string>

class vtkRenderWindow;

namespace sl {

// Opens the process's X connection on first use (DISPLAY); false with a one-line reason when
// there is no display or the server refuses. Later calls return the same answer.
bool open_x_display(std::string *error);
// Hands the process's connection to window (VTK then does not close it). Call before the
// window's first Render; a no-op when open_x_display failed.
void attach_x_display(vtkRenderWindow *window);

}  // namespace sl
