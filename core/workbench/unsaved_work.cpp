#include "core/workbench/unsaved_work.hpp"

#include <cstdlib>
#include <filesystem>
#include <functional>

namespace sb {

void UnsavedWork::observe(const std::string& document, double now_s) {
  const std::size_t h = std::hash<std::string>{}(document);
  if (h == current_) return;
  current_ = h;
  if (h == clean_ || h == autosaved_)
    dirty_since_s_.reset();
  else if (!dirty_since_s_)
    dirty_since_s_ = now_s;  // a continuous drag keeps the first change's time
}

void UnsavedWork::saved(const std::string& document) {
  clean_ = current_ = autosaved_ = std::hash<std::string>{}(document);
  dirty_since_s_.reset();
}

void UnsavedWork::autosaved() {
  autosaved_ = current_;
  dirty_since_s_.reset();
}

void UnsavedWork::restored(const std::string& document) {
  current_ = autosaved_ = std::hash<std::string>{}(document);
  clean_ = 0;
  dirty_since_s_.reset();
}

bool UnsavedWork::autosave_due(double now_s) const {
  return dirty() && current_ != autosaved_ && dirty_since_s_ && now_s - *dirty_since_s_ >= interval_s_;
}

namespace {
// $XDG_STATE_HOME/shearbench, else ~/.local/state/shearbench (current folder when HOME is unset).
std::filesystem::path state_folder() {
  namespace fs = std::filesystem;
  fs::path base;
  if (const char* x = std::getenv("XDG_STATE_HOME"); x && *x)
    base = x;
  else if (const char* h = std::getenv("HOME"); h && *h)
    base = fs::path(h) / ".local" / "state";
  else
    base = fs::current_path();
  return base / "shearbench";
}
}  // namespace

std::string default_autosave_path() {
  if (const char* p = std::getenv("SHEARBENCH_AUTOSAVE"); p && *p) return p;
  return (state_folder() / "autosave.json").string();
}

std::string default_session_path() { return (state_folder() / "session.json").string(); }

}  // namespace sb
