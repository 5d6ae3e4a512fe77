#include "widgets/frame_stats.hpp"

#include <GL/glew.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "core/base/free_memory.hpp"

namespace sb::ui {
namespace {

double steady_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// Nearest-rank percentile of a sorted, non-empty sample.
double percentile(const std::vector<double>& sorted, double q) {
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
  return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

// GL hands out the lowest names above the highest in use (Mesa: a growing key), so a fresh name bounds
// every live one; scanning up to it a little past is exact and costs microseconds per thousand names.
template <typename Gen, typename Del, typename Is>
int count_names(Gen gen, Del del, Is is) {
  GLuint probe = 0;
  gen(1, &probe);
  del(1, &probe);
  const GLuint top = std::min<GLuint>(probe + 64, 200000);
  int n = 0;
  for (GLuint name = 1; name <= top; ++name)
    if (name != probe && is(name)) ++n;
  return n;
}

}  // namespace

std::map<std::string, int> gl_object_counts() {
  std::map<std::string, int> c;
  c["textures"] = count_names([](GLsizei k, GLuint* p) { glGenTextures(k, p); },
                              [](GLsizei k, const GLuint* p) { glDeleteTextures(k, p); },
                              [](GLuint x) { return glIsTexture(x) == GL_TRUE; });
  c["buffers"] = count_names([](GLsizei k, GLuint* p) { glGenBuffers(k, p); },
                             [](GLsizei k, const GLuint* p) { glDeleteBuffers(k, p); },
                             [](GLuint x) { return glIsBuffer(x) == GL_TRUE; });
  c["framebuffers"] = count_names([](GLsizei k, GLuint* p) { glGenFramebuffers(k, p); },
                                  [](GLsizei k, const GLuint* p) { glDeleteFramebuffers(k, p); },
                                  [](GLuint x) { return glIsFramebuffer(x) == GL_TRUE; });
  c["renderbuffers"] = count_names([](GLsizei k, GLuint* p) { glGenRenderbuffers(k, p); },
                                   [](GLsizei k, const GLuint* p) { glDeleteRenderbuffers(k, p); },
                                   [](GLuint x) { return glIsRenderbuffer(x) == GL_TRUE; });
  c["vertex_arrays"] = count_names([](GLsizei k, GLuint* p) { glGenVertexArrays(k, p); },
                                   [](GLsizei k, const GLuint* p) { glDeleteVertexArrays(k, p); },
                                   [](GLuint x) { return glIsVertexArray(x) == GL_TRUE; });
  // Programs and shaders share one name space and are created one at a time.
  GLuint probe = glCreateShader(GL_VERTEX_SHADER);
  glDeleteShader(probe);
  int programs = 0, shaders = 0;
  for (GLuint name = 1; name <= std::min<GLuint>(probe + 64, 200000); ++name) {
    if (name == probe) continue;
    if (glIsProgram(name) == GL_TRUE)
      ++programs;
    else if (glIsShader(name) == GL_TRUE)
      ++shaders;
  }
  c["programs"] = programs;
  c["shaders"] = shaders;
  while (glGetError() != GL_NO_ERROR) {
  }  // the probes must not leave an error for the next draw
  return c;
}

long resident_kb() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (f == nullptr) return -1;
  long size = 0, resident = 0;
  const int got = std::fscanf(f, "%ld %ld", &size, &resident);
  std::fclose(f);
  return got == 2 ? resident * (sysconf(_SC_PAGESIZE) / 1024) : -1;
}

int open_fds() {
  std::error_code ec;
  int n = 0;
  for (std::filesystem::directory_iterator it("/proc/self/fd", ec), end; !ec && it != end; it.increment(ec)) ++n;
  return ec ? -1 : n;
}

FrameStats::FrameStats(const std::string& path, double interval_s)
    : out_(path, std::ios::app), path_(path), interval_s_(interval_s) {
  if (!out_) throw std::runtime_error("--stats " + path + ": cannot open for appending");
  start_s_ = window_start_s_ = steady_s();
}

void FrameStats::add(double frame_ms) {
  if (!enabled()) return;
  ms_.push_back(frame_ms);
  const double now = steady_s();
  if (now - window_start_s_ >= interval_s_) write_line(now);
}

void FrameStats::write_line(double now_s) {
  std::sort(ms_.begin(), ms_.end());
  const auto gl = gl_object_counts();
  const ResidentParts parts = resident_parts();
  const HeapUse heap = heap_use();
  char head[720];
  std::snprintf(
      head, sizeof head,
      "{\"t_s\": %.2f, \"window_s\": %.2f, \"frames\": %zu, \"frame_ms_p50\": %.3f, \"frame_ms_p95\": %.3f, "
      "\"frame_ms_max\": %.3f, \"rss_kb\": %ld, \"rss_anon_kb\": %ld, \"rss_file_kb\": %ld, \"heap_in_use_kb\": %ld, "
      "\"heap_free_kb\": %ld, \"fds\": %d, \"gl\": {",
      now_s - start_s_, now_s - window_start_s_, ms_.size(), percentile(ms_, 0.5), percentile(ms_, 0.95), ms_.back(),
      resident_kb(), parts.anon_kb, parts.file_kb, heap.in_use_kb, heap.free_kb, open_fds());
  out_ << head;
  bool first = true;
  for (const auto& [kind, n] : gl) {
    out_ << (first ? "" : ", ") << '"' << kind << "\": " << n;
    first = false;
  }
  // Every frame time of the window (unsorted order is not kept: sorted), so a reader can pool windows into
  // exact percentiles over any span (the soak's minutes).
  out_ << "}, \"frame_ms\": [";
  for (std::size_t i = 0; i < ms_.size(); ++i) {
    char v[32];
    std::snprintf(v, sizeof v, "%s%.2f", i ? ", " : "", ms_[i]);
    out_ << v;
  }
  out_ << "]}\n" << std::flush;
  ms_.clear();
  window_start_s_ = now_s;
}

}  // namespace sb::ui
