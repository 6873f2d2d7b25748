#include "movie.h"

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include "sl_tempfile.h"

namespace sl {

namespace {

std::string find_on_path(const std::string &name)
{
  const char *path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  size_t start = 0;
  while (start <= dirs.size()) {
    size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string candidate = (end > start ? dirs.substr(start, end - start) : ".") + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return "";
}

bool write_all(int fd, const char *data, size_t size)
{
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) return false;
    data += n;
    size -= (size_t)n;
  }
  return true;
}

}  // namespace

bool ffmpeg_available(std::string *error)
{
  if (!find_on_path("ffmpeg").empty()) return true;
  *error = "--movie needs ffmpeg on PATH (Debian: apt-get install ffmpeg); the frames themselves need no ffmpeg";
  return false;
}

bool write_movie(const std::vector<std::string> &pngs, const std::string &out, double fps, std::string *error)
{
  const std::string ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty()) return ffmpeg_available(error);
  char tmp[4096];
  sl_error err{};
  if (sl_temp_name(out.c_str(), tmp, sizeof tmp, &err)) {
    *error = err.message;
    return false;
  }
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.6g", fps);
  // The frames go through a pipe in series order, so any numbering (a --times step, several
  // files) makes a movie without ffmpeg's pattern rules.
  const char *args[] = {ffmpeg.c_str(), "-hide_banner", "-loglevel", "error", "-y", "-f", "image2pipe", "-framerate",
                        rate, "-c:v", "png", "-i", "-", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264",
                        "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4", tmp, nullptr};
  int fds[2];
  if (pipe(fds) != 0) {
    *error = out + ": cannot create a pipe to ffmpeg";
    return false;
  }
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]), close(fds[1]);
    *error = out + ": cannot start ffmpeg";
    return false;
  }
  if (pid == 0) {
    dup2(fds[0], STDIN_FILENO);
    close(fds[0]), close(fds[1]);
    execv(ffmpeg.c_str(), const_cast<char *const *>(args));
    _exit(127);
  }
  close(fds[0]);
  // A dying ffmpeg must give a write error here, not kill stormlight with SIGPIPE.
  struct sigaction ignore {}, previous {};
  ignore.sa_handler = SIG_IGN;
  sigaction(SIGPIPE, &ignore, &previous);
  bool fed = true;
  std::string unreadable;
  for (const std::string &png : pngs) {
    std::ifstream in(png, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) unreadable = png;
    if (bytes.empty()) unreadable = png;
    if (!unreadable.empty() || !write_all(fds[1], bytes.data(), bytes.size())) {
      fed = false;
      break;
    }
  }
  close(fds[1]);
  int status = 0;
  waitpid(pid, &status, 0);
  sigaction(SIGPIPE, &previous, nullptr);
  if (!unreadable.empty()) {
    unlink(tmp);
    *error = unreadable + ": cannot read the frame for the movie";
    return false;
  }
  if (!fed || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    unlink(tmp);
    *error = out + ": ffmpeg failed (exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
             "); its message is above";
    return false;
  }
  if (sl_temp_commit(tmp, out.c_str(), &err)) {
    *error = err.message;
    return false;
  }
  return true;
}

}  // namespace sl
