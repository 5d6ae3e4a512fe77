#include "core/workbench/work_keeper.hpp"

#include <filesystem>

namespace sb {

std::string work_fingerprint(const SessionFile& file) {
  nlohmann::ordered_json j = session_to_json(file);
  j.erase("step");
  j["display"].erase("camera");  // orbiting the view is not work to ask about (it is saved with the rest)
  // With auto scale on, the arrow gain and colour range follow the fields: derived, not edited.
  if (j["display"]["auto_scale"].get<bool>()) j.erase("display");
  return j.dump();
}

WorkKeeper::WorkKeeper(double autosave_interval_s, std::string autosave_path, Source source)
    : work_(autosave_interval_s), autosave_path_(std::move(autosave_path)), source_(std::move(source)) {}

std::optional<WorkKeeper::Check> WorkKeeper::tick(double now_s) {
  constexpr double kCheckEveryS = 0.5;  // building the document costs ~ a millisecond for long paths
  if (now_s - last_check_s_ < kCheckEveryS) return std::nullopt;
  last_check_s_ = now_s;
  // The baseline is taken once the physics has applied the opened session's edits.
  if (baseline_pending_ != WorkBaseline::kNone && source_.pending_edits() == 0) {
    if (baseline_pending_ == WorkBaseline::kClean)
      work_.saved(fingerprint());
    else
      work_.restored(fingerprint());
    baseline_pending_ = WorkBaseline::kNone;
  }
  work_.observe(fingerprint(), now_s);
  Check check;
  check.dirty = work_.dirty();
  if (work_.autosave_due(now_s)) {
    try {
      save_session_file(autosave_path_, source_.document());
      work_.autosaved();
    } catch (const std::exception& e) {
      check.autosave_error = e.what();
    }
  }
  return check;
}

void WorkKeeper::saved_to(const std::string& path) {
  work_.saved(fingerprint());
  saved_once_ = true;
  std::error_code ec;
  // Saved: the autosave is stale, unless the user just saved over the autosave file itself.
  if (!std::filesystem::equivalent(path, autosave_path_, ec)) std::filesystem::remove(autosave_path_, ec);
}

bool WorkKeeper::has_autosave() const {
  std::error_code ec;
  return std::filesystem::is_regular_file(autosave_path_, ec);
}

void WorkKeeper::discard_autosave() {
  std::error_code ec;
  std::filesystem::remove(autosave_path_, ec);
}

bool WorkKeeper::dirty_now(double now_s) {
  if (baseline_pending_ == WorkBaseline::kNone) work_.observe(fingerprint(), now_s);
  return work_.dirty();
}

bool WorkKeeper::unsaved_on_close(double now_s) { return dirty_now(now_s) && !close_confirmed_; }

}  // namespace sb
