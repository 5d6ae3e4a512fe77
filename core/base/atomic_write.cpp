#include "core/base/atomic_write.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "core/base/error.hpp"

namespace fs = std::filesystem;

namespace sb {
namespace {

// Test hook: SHEARBENCH_TEST_WRITE_DELAY_MS holds every write between "temporary complete" and
// "rename", so a test can kill the process at exactly the moment that matters.
void test_delay_before_rename() {
  const char* ms = std::getenv("SHEARBENCH_TEST_WRITE_DELAY_MS");
  if (ms == nullptr) return;
  const long delay = std::strtol(ms, nullptr, 10);
  if (delay > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delay));
}

void remove_quietly(const fs::path& p) {
  std::error_code ec;
  fs::remove(p, ec);
}

}  // namespace

std::string atomic_temporary_path(const std::string& path) {
  const fs::path target(path);
  const fs::path name = "." + target.filename().string() + ".tmp." + std::to_string(::getpid());
  return (target.has_parent_path() ? target.parent_path() / name : name).string();
}

void write_file_atomic(const std::string& path, std::string_view content) {
  const fs::path target(path);
  if (target.filename().empty()) throw InputError(path, "output path names a folder, not a file");
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  if (ec) throw InputError(path, "cannot create the output folder: " + ec.message());
  if (fs::is_directory(target, ec)) throw InputError(path, "output path is an existing folder");
  const fs::path tmp = atomic_temporary_path(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path, "cannot write (temporary file " + tmp.string() + ")");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      out.close();
      remove_quietly(tmp);
      throw InputError(path, "write failed (disk full?)");
    }
  }
  test_delay_before_rename();
  fs::rename(tmp, target, ec);
  if (ec) {
    remove_quietly(tmp);
    throw InputError(path, "cannot rename the temporary file into place: " + ec.message());
  }
}

void write_png_atomic(const std::string& path, int rows, int cols, int channels, const unsigned char* data) {
  if (channels != 1 && channels != 3 && channels != 4) throw InputError(path, "PNG needs 1, 3 or 4 channels");
  const cv::Mat image(rows, cols, CV_8UC(channels), const_cast<unsigned char*>(data));
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw InputError(path, "could not encode the image as PNG");
  write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace sb
