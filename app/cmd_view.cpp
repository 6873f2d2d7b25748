// stormlight view: an interactive window on a storm. The viewer keeps render's session (the
// storm, air, tables, renderer and GPU pass: render_session.h) and draws each view with the batch
// renderer's own code (the GPU pass, falling back to the CPU), so a camera change costs an eye
// pass, a sun change the light volume, the exposure a tone map. Mouse and keys change the camera,
// the sun, xi and the exposure; 'p' saves the view as a scene file and an EXR that
// `stormlight render --scene` reproduces exactly. --script plays key and mouse events through
// the same interactor (tests, demos) and prints what each one cost.
#include <vtkCallbackCommand.h>
#include <vtkImageActor.h>
#include <vtkImageMapper3D.h>
#include <vtkImageData.h>
#include <vtkInteractorStyleUser.h>
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkCamera.h>

#include <cjson/cJSON.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "render_session.h"
#include "sl_image_io.h"
#include "x_display.h"
#include "scene.h"
#include "sl_sky.h"
#include "sl_storm.h"
#include "vtk_png.h"

bool sl_parse_iso8601_utc(const std::string &text, sl_utc *out, std::string *why);  // cmd_sun.cpp

namespace {

// What the view shows, as render's options.
struct ViewState {
  std::string data;
  long time = 0, width = 480, height = 360;
  double sun_az = 200, sun_el = 30, view_az = 200, view_el = 12, fov = 40, xi = 0.05, exposure = 12;
  bool explicit_camera = false;
  double position[3] = {0, 0, 0}, target[3] = {0, 0, 0};
  std::string lighting = "multiple";
  // render's other options, as given (the viewer does not change them): forwarded and saved.
  std::vector<std::pair<std::string, std::string>> options;
  std::vector<std::string> flags;
  // The date the sun's angles come from (keys move it), over the grid's centre.
  bool have_date = false;
  sl_utc date{};
  double lat = 0, lon = 0;
  int ntimes = 1;
  std::vector<std::string> times;  // the file's times as ISO 8601 (empty when it has none)
};

// The sun's angles for the state's date (what render computes for --date).
bool place_sun(ViewState &s, std::string *why)
{
  sl_solar_position pos;
  sl_error err{};
  if (sl_solar_position_compute(&s.date, s.lat, s.lon, nullptr, &pos, &err)) {
    *why = err.message;
    return false;
  }
  s.sun_az = pos.azimuth_deg;
  s.sun_el = pos.elevation_deg;
  return true;
}

// The grid's centre column at a time step (what render places the sun over; a moving nest's
// centre moves with the series).
bool grid_centre(ViewState &s, std::string *why)
{
  sl_storm_frame frame;
  sl_load_options lo{};
  lo.time_index = (int)s.time;
  sl_error err{};
  if (sl_storm_load(s.data.c_str(), &lo, &frame, &err)) {
    *why = err.message;
    return false;
  }
  s.lat = frame.center_lat, s.lon = frame.center_lon;
  sl_storm_frame_free(&frame);
  return true;
}

std::string num(double v)
{
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string vec(const double v[3]) { return num(v[0]) + "," + num(v[1]) + "," + num(v[2]); }

std::vector<std::string> render_arguments(const ViewState &s)
{
  std::vector<std::string> a = {"render", s.data, "--time", std::to_string(s.time), "--width", std::to_string(s.width),
                                "--height", std::to_string(s.height), "--sun-azimuth", num(s.sun_az), "--sun-elevation",
                                num(s.sun_el), "--fov", num(s.fov), "--xi", num(s.xi), "--exposure", num(s.exposure),
                                "--lighting", s.lighting};
  for (const auto &kv : s.options) a.push_back("--" + kv.first), a.push_back(kv.second);
  for (const std::string &f : s.flags) a.push_back("--" + f);
  if (s.explicit_camera) {
    for (const std::string &x : {std::string("--camera-position"), vec(s.position), std::string("--camera-target"), vec(s.target)})
      a.push_back(x);
  } else {
    for (const std::string &x : {std::string("--view-azimuth"), num(s.view_az), std::string("--view-elevation"), num(s.view_el)})
      a.push_back(x);
  }
  return a;
}

bool write_scene(const ViewState &s, const std::string &path, std::string *why)
{
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "comment", "saved by stormlight view");
  cJSON_AddStringToObject(root, "data", s.data.c_str());
  cJSON_AddNumberToObject(root, "time", (double)s.time);
  cJSON_AddNumberToObject(root, "width", (double)s.width);
  cJSON_AddNumberToObject(root, "height", (double)s.height);
  cJSON_AddNumberToObject(root, "sun-azimuth", s.sun_az);
  cJSON_AddNumberToObject(root, "sun-elevation", s.sun_el);
  cJSON_AddNumberToObject(root, "fov", s.fov);
  cJSON_AddNumberToObject(root, "xi", s.xi);
  cJSON_AddNumberToObject(root, "exposure", s.exposure);
  cJSON_AddStringToObject(root, "lighting", s.lighting.c_str());
  for (const auto &kv : s.options) cJSON_AddStringToObject(root, kv.first.c_str(), kv.second.c_str());
  for (const std::string &f : s.flags) cJSON_AddTrueToObject(root, f.c_str());
  if (s.explicit_camera) {
    cJSON_AddItemToObject(root, "camera-position", cJSON_CreateDoubleArray(s.position, 3));
    cJSON_AddItemToObject(root, "camera-target", cJSON_CreateDoubleArray(s.target, 3));
  } else {
    cJSON_AddNumberToObject(root, "view-azimuth", s.view_az);
    cJSON_AddNumberToObject(root, "view-elevation", s.view_el);
  }
  char *text = cJSON_Print(root);
  cJSON_Delete(root);
  const std::string tmp = path + ".tmp";
  std::ofstream out(tmp);
  out << text << "\n";
  std::free(text);
  out.close();
  if (!out || std::rename(tmp.c_str(), path.c_str()) != 0) {
    *why = path + ": cannot write the scene file";
    return false;
  }
  return true;
}

// What a change invalidates, from the most to the least: a new time step reloads the storm (a
// new session); the sun relights the volume; xi and the camera redraw the eye pass (and the sky
// for the view); the exposure only tone-maps the kept HDR frame again.
enum class Change { Time, Sun, Xi, Camera, Exposure, Quality };

const char *change_name(Change c)
{
  switch (c) {
    case Change::Time: return "time step (reload)";
    case Change::Sun: return "sun (light volume + eye pass)";
    case Change::Xi: return "xi (eye pass)";
    case Change::Camera: return "camera (eye pass)";
    case Change::Exposure: return "exposure (tone map)";
    case Change::Quality: return "march samples (eye pass)";
  }
  return "";
}

class Viewer {
 public:
  ViewState state;
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkImageActor> actor;
  vtkNew<vtkImageData> shown;
  vtkNew<vtkRenderWindowInteractor> interactor;
  vtkNew<vtkInteractorStyleUser> style;
  bool dragging = false, panning = false;
  int last[2] = {0, 0};
  int failures = 0;
  // The prepared storm, air, tables, renderer and GPU pass for state.time (render_session.h).
  std::unique_ptr<sl::RenderSession> session;
  long session_time = -1;
  sl_camera camera{};
  sl_image hdr{}, volume{}, background{};
  std::string cpu_note;  // why the GPU pass could not draw the last frame (said once)
  double last_seconds = 0;
  char parts[160] = "";  // where the last redraw's time went
  Change last_change = Change::Time;

  ~Viewer()
  {
    session.reset();
    for (sl_image *img : {&hdr, &volume, &background}) sl_image_free(img);
  }

  // render's --march-samples as the state carries it (1 when not given).
  int march_samples() const
  {
    for (const auto &kv : state.options)
      if (kv.first == "march-samples") return std::atoi(kv.second.c_str());
    return 1;
  }
  void set_option(const std::string &name, const std::string &value)
  {
    for (auto &kv : state.options)
      if (kv.first == name) {
        kv.second = value;
        return;
      }
    state.options.emplace_back(name, value);
  }

  // The camera render places for the state (render_main's framing, or the explicit camera).
  void PlaceCamera()
  {
    double lo[3], hi[3];
    sl_renderer_content_bounds(session->renderer, lo, hi);
    sl_camera_frame(lo, hi, state.view_az, state.view_el, state.fov, (int)state.width, (int)state.height, &camera);
    if (state.explicit_camera)
      for (int a = 0; a < 3; ++a) camera.position[a] = state.position[a], camera.target[a] = state.target[a];
  }

  bool Prepare(std::string *why)
  {
    session.reset();
    // The view's state as render's arguments (without the command's name), read by the C parser.
    std::vector<std::string> args = render_arguments(state);
    std::vector<char *> argv;
    for (size_t i = 1; i < args.size(); ++i) argv.push_back(&args[i][0]);
    std::unique_ptr<sl_settings> settings(new sl_settings);
    sl_settings_defaults(settings.get());
    sl_error err{};
    if (sl_settings_parse_args(settings.get(), (int)argv.size(), argv.data(), &err) ||
        sl_settings_check(settings.get(), &err)) {
      *why = err.message;
      return false;
    }
    std::unique_ptr<sl::RenderSession> s(new sl::RenderSession);
    s->for_gpu = true;
    int exit_code = 1;
    if (!s->prepare(*settings, true, why, &exit_code)) return false;
    session = std::move(s);
    session_time = state.time;
    return true;
  }

  // Redraws what `change` invalidates and shows the frame; times it.
  bool Redraw(Change change)
  {
    const double t0 = sl::now_seconds();
    std::string why;
    sl_error err{};
    bool ok = true;
    if (!session || state.time != session_time) change = Change::Time;
    parts[0] = 0;
    if (change == Change::Time) ok = Prepare(&why);
    else if (change == Change::Sun) ok = session->set_sun(state.sun_el, state.sun_az, &why);
    else if (change == Change::Xi) session->set_xi(state.xi);
    else if (change == Change::Quality) ok = session->set_march_samples(march_samples(), &why);
    if (ok && change != Change::Exposure) {
      PlaceCamera();
      if (hdr.width != camera.width || hdr.height != camera.height) {
        for (sl_image *img : {&hdr, &volume, &background}) {
          sl_image_free(img);
          if (ok && sl_image_alloc(img, camera.width, camera.height, &err)) ok = false, why = err.message;
        }
      }
      bool gpu_done = false;
      std::string gpu_note;
      sl_render_stats stats{};
      const double t1 = sl::now_seconds();
      ok = ok && session->draw(camera, true, &volume, &background, &stats, &gpu_done, &gpu_note, &why);
      const double t2 = sl::now_seconds();
      ok = ok && session->composite(camera, background, volume, &hdr, nullptr);
      std::snprintf(parts, sizeof parts, "(light %.3f, eye %.3f, sky+resolve %.3f, composite %.3f s)",
                    stats.light_seconds, stats.eye_seconds, t2 - t1 - stats.light_seconds - stats.eye_seconds,
                    sl::now_seconds() - t2);
      if (ok && !gpu_done && gpu_note != cpu_note)
        std::fprintf(stderr, "view: the GPU pass cannot draw this (%s); drawing on the CPU\n", gpu_note.c_str());
      if (ok) cpu_note = gpu_done ? "" : gpu_note;
    }
    if (!ok) {
      std::fprintf(stderr, "view: %s\n", why.empty() ? "the frame could not be drawn" : why.c_str());
      ++failures;
      return false;
    }
    Show();
    last_seconds = sl::now_seconds() - t0;
    last_change = change;
    return true;
  }

  // The kept HDR frame tone-mapped at the state's exposure (render's PNG curve) into the window.
  void Show()
  {
    const int w = hdr.width, h = hdr.height;
    shown->SetDimensions(w, h, 1);
    shown->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
    auto *px = static_cast<unsigned char *>(shown->GetScalarPointer());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          // rows from the top in the frame, from the bottom in VTK's image
          const float v = sl_tonemap(hdr.rgba[4 * ((size_t)(h - 1 - y) * w + x) + c], (float)state.exposure);
          px[3 * ((size_t)y * w + x) + c] = (unsigned char)std::lrint(255.0f * std::min(1.0f, std::max(0.0f, v)));
        }
    shown->Modified();
    actor->GetMapper()->SetInputData(shown);
    renderer->ResetCamera();
    renderer->GetActiveCamera()->ParallelProjectionOn();
    renderer->ResetCamera();
    renderer->GetActiveCamera()->SetParallelScale(0.5 * h);
    window->Render();
  }

  // Orbit: the camera turns around its target (or the cloud) by the drag, 0.25 degree a pixel.
  void Orbit(double dx, double dy)
  {
    const double daz = -0.25 * dx, del = -0.25 * dy;
    if (!state.explicit_camera) {
      state.view_az = std::fmod(state.view_az + daz + 360.0, 360.0);
      state.view_el = std::max(-89.0, std::min(89.0, state.view_el + del));
      return;
    }
    double v[3];
    for (int a = 0; a < 3; ++a) v[a] = state.position[a] - state.target[a];
    const double r = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double az = std::atan2(v[0], v[1]) * 180.0 / M_PI + daz, el = std::asin(v[2] / r) * 180.0 / M_PI + del;
    el = std::max(-89.0, std::min(89.0, el));
    const double a = az * M_PI / 180.0, e = el * M_PI / 180.0;
    state.position[0] = state.target[0] + r * std::sin(a) * std::cos(e);
    state.position[1] = state.target[1] + r * std::cos(a) * std::cos(e);
    state.position[2] = state.target[2] + r * std::sin(e);
  }

  // Pan: camera and target move together in the image plane so that the point under the cursor
  // at the target's distance follows a drag of (dx, dy) pixels (x right, y up). The camera
  // becomes explicit (the framing from view-azimuth/elevation is always centred).
  void Pan(double dx, double dy)
  {
    if (!session) return;
    PlaceCamera();
    double fwd[3], right[3], up[3], len = 0;
    sl_camera_basis(&camera, fwd, right, up);
    for (int a = 0; a < 3; ++a) len += (camera.target[a] - camera.position[a]) * (camera.target[a] - camera.position[a]);
    len = std::sqrt(len);
    const double metres_per_pixel = 2.0 * len * std::tan(0.5 * camera.fov_deg * M_PI / 180.0) / camera.height;
    for (int a = 0; a < 3; ++a) {
      const double shift = -metres_per_pixel * (dx * right[a] + dy * up[a]);
      state.position[a] = camera.position[a] + shift;
      state.target[a] = camera.target[a] + shift;
    }
    state.explicit_camera = true;
  }

  bool Save(const std::string &prefix)
  {
    std::string why;
    // The EXR carries the saved scene's text in its header, as render --scene writes it.
    const bool saved = write_scene(state, prefix + ".json", &why);
    std::stringstream text;
    if (saved) text << std::ifstream(prefix + ".json").rdbuf();
    if (!saved || !sl::write_frame(prefix + ".exr", camera, hdr, session->scene.sun_direction, text.str(), Floats(),
                                   (float)state.exposure, &why)) {
      std::fprintf(stderr, "view: %s\n", why.c_str());
      ++failures;
      return false;
    }
    std::printf("view: saved %s.json and %s.exr\n", prefix.c_str(), prefix.c_str());
    return true;
  }

  bool Floats() const
  {
    for (const std::string &f : state.flags)
      if (f == "float") return true;
    return false;
  }

  std::string save_prefix = "view";

  void Key(const std::string &k)
  {
    Change change = Change::Camera;
    bool redraw = true;
    if (k == "Left") Orbit(-20, 0);
    else if (k == "Right") Orbit(20, 0);
    else if (k == "Up") Orbit(0, -20);
    else if (k == "Down") Orbit(0, 20);
    else if (k == "j") Pan(-20, 0);
    else if (k == "l") Pan(20, 0);
    else if (k == "i") Pan(0, 20);
    else if (k == "k") Pan(0, -20);
    else if (k == "a") state.sun_az = std::fmod(state.sun_az - 5.0 + 360.0, 360.0), change = Change::Sun;
    else if (k == "d") state.sun_az = std::fmod(state.sun_az + 5.0, 360.0), change = Change::Sun;
    else if (k == "w") state.sun_el = std::min(90.0, state.sun_el + 2.0), change = Change::Sun;
    else if (k == "s") state.sun_el = std::max(-10.0, state.sun_el - 2.0), change = Change::Sun;
    else if (k == "x") state.xi = std::max(0.0, state.xi - 0.01), change = Change::Xi;
    else if (k == "X") state.xi += 0.01, change = Change::Xi;
    else if (k == "m" || k == "M") {
      /* The light-volume march's samples per cell (render's --march-samples), kept with render's
       * other options so that a saved scene reproduces the frame. */
      const int n = std::max(1, std::min(8, march_samples() + (k == "m" ? -1 : 1)));
      set_option("march-samples", std::to_string(n));
      change = Change::Quality;
    } else if (k == "plus" || k == "equal") state.exposure *= 1.25, change = Change::Exposure;
    else if (k == "minus") state.exposure /= 1.25, change = Change::Exposure;
    else if (k == "z") state.fov = std::max(2.0, state.fov / 1.1);
    else if (k == "Z") state.fov = std::min(120.0, state.fov * 1.1);
    else if ((k == "h" || k == "H" || k == "n" || k == "N") && state.have_date) {
      sl_utc_add_seconds(&state.date, 3600.0 * (k == "h" ? -1 : k == "H" ? 1 : k == "n" ? -24 : 24), nullptr);
      std::string why;
      change = Change::Sun;
      if (!place_sun(state, &why)) std::fprintf(stderr, "view: %s\n", why.c_str()), redraw = false;
      else
        std::printf("view: %04d-%02d-%02d %02d:%02d UTC, sun elevation %.2f, azimuth %.2f\n", state.date.year,
                    state.date.month, state.date.day, state.date.hour, state.date.minute, state.sun_el, state.sun_az);
    } else if (k == "t" || k == "T") {
      state.time = k == "t" ? std::max(0L, state.time - 1) : std::min((long)state.ntimes - 1, state.time + 1);
      change = Change::Time;
      // The date follows the series: the sun of the new step's own time.
      std::string why;
      if (state.time < (long)state.times.size() && sl_parse_iso8601_utc(state.times[state.time], &state.date, &why) &&
          (!grid_centre(state, &why) || !place_sun(state, &why)))
        std::fprintf(stderr, "view: %s\n", why.c_str());
    }
    else if (k == "p") {
      Save(save_prefix);
      redraw = false;
    } else redraw = false;
    if (redraw) Redraw(change);
  }
};

void on_event(vtkObject *caller, unsigned long event, void *client, void *)
{
  auto *v = static_cast<Viewer *>(client);
  auto *iren = static_cast<vtkRenderWindowInteractor *>(caller);
  int *p = iren->GetEventPosition();
  switch (event) {
    case vtkCommand::KeyPressEvent:
      if (iren->GetKeySym()) v->Key(iren->GetKeySym());
      break;
    case vtkCommand::LeftButtonPressEvent:
      v->dragging = true, v->last[0] = p[0], v->last[1] = p[1];
      break;
    case vtkCommand::LeftButtonReleaseEvent:
      if (v->dragging) {
        v->Orbit(p[0] - v->last[0], v->last[1] - p[1]);
        v->dragging = false;
        v->Redraw(Change::Camera);
      }
      break;
    case vtkCommand::MiddleButtonPressEvent:
      v->panning = true, v->last[0] = p[0], v->last[1] = p[1];
      break;
    case vtkCommand::MiddleButtonReleaseEvent:
      if (v->panning) {
        v->Pan(p[0] - v->last[0], p[1] - v->last[1]);
        v->panning = false;
        v->Redraw(Change::Camera);
      }
      break;
    case vtkCommand::MouseWheelForwardEvent:
      v->Key("z");
      break;
    case vtkCommand::MouseWheelBackwardEvent:
      v->Key("Z");
      break;
    default:
      break;
  }
}

// Plays a script through the interactor: "key SYM", "drag DX DY", "wheel N" (+ in, - out),
// "save PREFIX"; '#' starts a comment.
bool play(Viewer &v, const std::string &path)
{
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "view: %s: cannot read the script\n", path.c_str());
    return false;
  }
  std::string line;
  int number = 0;
  vtkRenderWindowInteractor *iren = v.interactor;
  while (std::getline(in, line)) {
    ++number;
    std::stringstream ss(line);
    std::string cmd;
    if (!(ss >> cmd) || cmd[0] == '#') continue;
    if (cmd == "key") {
      std::string sym;
      ss >> sym;
      iren->SetKeySym(sym.c_str());
      iren->SetKeyCode(sym.size() == 1 ? sym[0] : 0);
      iren->InvokeEvent(vtkCommand::KeyPressEvent);
    } else if (cmd == "drag" || cmd == "pan") {
      // DX right, DY down on the screen (a mouse's motion); VTK's event positions count y up.
      int dx = 0, dy = 0;
      ss >> dx >> dy;
      const int x0 = (int)v.state.width / 2, y0 = (int)v.state.height / 2;
      const bool pan = cmd == "pan";
      iren->SetEventPosition(x0, y0);
      iren->InvokeEvent(pan ? vtkCommand::MiddleButtonPressEvent : vtkCommand::LeftButtonPressEvent);
      iren->SetEventPosition(x0 + dx, y0 - dy);
      iren->InvokeEvent(vtkCommand::MouseMoveEvent);
      iren->InvokeEvent(pan ? vtkCommand::MiddleButtonReleaseEvent : vtkCommand::LeftButtonReleaseEvent);
    } else if (cmd == "wheel") {
      int n = 0;
      ss >> n;
      for (int i = 0; i < std::abs(n); ++i)
        iren->InvokeEvent(n > 0 ? vtkCommand::MouseWheelForwardEvent : vtkCommand::MouseWheelBackwardEvent);
    } else if (cmd == "save") {
      std::string prefix;
      ss >> prefix;
      if (!v.Save(prefix)) return false;
    } else {
      std::fprintf(stderr, "view: %s:%d: unknown command '%s' (key, drag, pan, wheel, save)\n", path.c_str(), number,
                   cmd.c_str());
      return false;
    }
    if (v.failures) return false;
    if (cmd != "save" && v.last_seconds > 0)
      std::printf("view: %-12s %-32s %.3f s %s\n", line.c_str(), change_name(v.last_change), v.last_seconds, v.parts);
    v.last_seconds = 0;
  }
  return true;
}

}  // namespace

int sl_cmd_view(int argc, char **argv)
{
  // A scene file's options come first; the command line overrides them (as in render).
  std::vector<std::string> args = {"view"};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scene" && i + 1 < argc) {
      std::vector<std::string> from_scene;
      std::string error;
      if (!sl::scene_to_arguments(argv[++i], &from_scene, &error)) return sl::fail("view", error, 2);
      args.insert(args.begin() + 1, from_scene.begin(), from_scene.end());
    } else {
      args.push_back(a);
    }
  }
  std::vector<char *> cargv;
  for (std::string &s : args) cargv.push_back(&s[0]);
  sl::Options o("view", "FILE | --scene S [options]",
                "An interactive window on a storm, drawn with the GPU pass (render --gpu; the CPU when the OpenGL\n"
                "context cannot). Mouse: left drag orbits, middle drag pans, the wheel zooms. Keys: arrows orbit;\n"
                "i/j/k/l pan; a/d sun azimuth -/+ 5 degrees; w/s sun elevation +/- 2; h/H the date -/+ 1 hour, n/N -/+ 1 day (the sun follows);\n"
                "t/T the series' time step -/+ 1; x/X xi -/+ 0.01; m/M march samples per cell -/+ 1; -/+ exposure; z/Z zoom; p saves the view\n"
                "as PREFIX.json (a scene for render --scene) and PREFIX.exr. --script plays events and exits.");
  sl::declare_render_options(o);
  o.option("scene", "FILE.json", "start from a scene file");
  o.option("script", "FILE", "play 'key SYM', 'drag DX DY', 'pan DX DY', 'wheel N', 'save PREFIX' lines, then exit,\n"
                       "printing what each cost");
  o.option("save", "PREFIX", "where 'p' saves the view", "view");
  const int early = sl::parse_or_exit(o, (int)cargv.size(), cargv.data());
  if (early >= 0) return early;
  if (o.positional().size() != 1) return sl::fail("view", "give exactly one storm FILE (or a --scene with data)", 2);
  std::string display_error;
  if (!sl::have_display(&display_error)) return sl::fail("view", display_error);
  Viewer v;
  ViewState &s = v.state;
  s.data = o.positional()[0];
  if (!o.integer("width", &s.width, 1, 8192) || !o.integer("height", &s.height, 1, 8192) ||
      !o.integer("time", &s.time, 0, 1 << 20) || !o.number("fov", &s.fov) || !o.number("xi", &s.xi) ||
      !o.number("exposure", &s.exposure) || !o.number("view-azimuth", &s.view_az) ||
      !o.number("view-elevation", &s.view_el))
    return sl::fail("view", o.error(), 2);
  if (o.has("sun-azimuth") && (!o.number("sun-azimuth", &s.sun_az) || !o.number("sun-elevation", &s.sun_el)))
    return sl::fail("view", o.error(), 2);
  // The sun: the given angles, or the date's (--date or the file's time) as render places it.
  {
    std::unique_ptr<sl_storm_info> info(new sl_storm_info);
    sl_error err{};
    if (sl_storm_read_info(s.data.c_str(), info.get(), &err)) return sl::fail("view", err.message);
    s.ntimes = info->ntimes > 0 ? info->ntimes : 1;
    std::string why, when;
    if (!grid_centre(s, &why)) return sl::fail("view", why);
    for (int i = 0; info->has_times && i < s.ntimes; ++i) {
      std::string t = info->sun_times[i];
      for (char &ch : t)
        if (ch == '_') ch = 'T';
      s.times.push_back(t + "Z");
    }
    if (o.has("date")) when = o.str("date");
    else if (s.time < (long)s.times.size()) when = s.times[s.time];
    if (!when.empty()) {
      if (!sl_parse_iso8601_utc(when, &s.date, &why)) return sl::fail("view", when + ": " + why, 2);
      s.have_date = true;
    }
    if (!o.has("sun-azimuth")) {
      if (!s.have_date) return sl::fail("view", s.data + ": no sun angles, no --date and no times in the file", 2);
      if (!place_sun(s, &why)) return sl::fail("view", why);
    }
  }
  s.lighting = o.str("lighting");
  // Every other option of the table as given (the view's own state above is not among them).
  static const std::set<std::string> kViewState = {
      "out",  "time", "width", "height", "sun-azimuth", "sun-elevation", "date", "fov", "xi", "exposure",
      "lighting", "view-azimuth", "view-elevation", "camera-position", "camera-target"};
  for (int i = 0; i < sl_settings_option_count; ++i) {
    const sl_option &opt = sl_settings_options[i];
    if (kViewState.count(opt.name) || !o.has(opt.name)) continue;
    if (opt.type == SL_OPTION_FLAG) s.flags.push_back(opt.name);
    else s.options.emplace_back(opt.name, o.str(opt.name));
  }
  if (o.has("camera-position") || o.has("camera-target")) {
    if (!o.has("camera-position") || !o.has("camera-target"))
      return sl::fail("view", "give both --camera-position and --camera-target, or neither", 2);
    if (!o.vec3("camera-position", s.position) || !o.vec3("camera-target", s.target)) return sl::fail("view", o.error(), 2);
    s.explicit_camera = true;
  }
  v.save_prefix = o.str("save");
  sl::attach_x_display(v.window);  // the process's one X connection (x_display.h)
  v.window->SetSize((int)s.width, (int)s.height);
  v.window->SetWindowName("stormlight view");
  v.window->AddRenderer(v.renderer);
  v.renderer->AddActor(v.actor);
  v.interactor->SetRenderWindow(v.window);
  v.interactor->SetInteractorStyle(v.style);
  vtkNew<vtkCallbackCommand> callback;
  callback->SetCallback(on_event);
  callback->SetClientData(&v);
  for (unsigned long e : {vtkCommand::KeyPressEvent, vtkCommand::LeftButtonPressEvent, vtkCommand::LeftButtonReleaseEvent,
                          vtkCommand::MiddleButtonPressEvent, vtkCommand::MiddleButtonReleaseEvent,
                          vtkCommand::MouseWheelForwardEvent, vtkCommand::MouseWheelBackwardEvent})
    v.interactor->AddObserver(e, callback);
  int rc = 0;
  if (o.has("script")) {
    v.window->SetOffScreenRendering(1);
    v.interactor->Initialize();
    if (!v.Redraw(Change::Time)) rc = 1;
    else {
      std::printf("view: %-12s %-32s %.3f s %s\n", "(open)", change_name(Change::Time), v.last_seconds, v.parts);
      if (!play(v, o.str("script"))) rc = 1;
    }
  } else {
    v.interactor->Initialize();
    if (!v.Redraw(Change::Time)) rc = 1;
    else v.interactor->Start();
  }
  return rc;
}
