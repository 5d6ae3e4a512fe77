#include "app/session_loader.hpp"

#include "core/base/error.hpp"

namespace sb::app {

void SessionLoader::start(const SessionOptions& options, WorkBaseline baseline, const std::string& what,
                          std::function<void()> then, double now_s) {
  if (pending_) throw InputError(what, "still opening " + request_.what + ": wait for it, then open again");
  pending_ = true;
  request_ = Opened{nullptr, "", options, baseline, what, std::move(then), 0};
  started_s_ = now_s;
  job_.start(Status{Status::Phase::kRunning, nullptr, ""},
             [options, wake = wake_](const std::atomic<bool>&, StatusJob<Status>& job) {
               Status done;
               try {
                 done.session = std::make_shared<Session>(open_session(options));
                 done.phase = Status::Phase::kDone;
               } catch (const std::exception& e) {
                 done.error = e.what();
                 done.phase = Status::Phase::kFailed;
               }
               job.update([&](Status& s) { s = std::move(done); });
               if (wake) wake();
             });
}

std::optional<SessionLoader::Opened> SessionLoader::take_finished(double now_s) {
  if (!pending_) return std::nullopt;
  Status st = job_.status();
  if (st.running()) return std::nullopt;
  pending_ = false;
  Opened opened = std::move(request_);
  request_.then = nullptr;
  if (st.phase == Status::Phase::kDone) opened.session = std::move(st.session);
  opened.error = std::move(st.error);
  opened.read_s = now_s - started_s_;
  return opened;
}

}  // namespace sb::app
