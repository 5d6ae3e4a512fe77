#pragma once
// Opening a session on a worker (core/base/status_job.hpp) while the window stays live: the frame loop
// starts an open, shows what is opening, and takes the finished one at the start of a frame (its one sync
// point), with what it was asked to do afterwards.
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "app/session.hpp"
#include "core/base/status_job.hpp"
#include "core/workbench/work_keeper.hpp"

namespace sb::app {

class SessionLoader {
 public:
  // A finished open, taken once.
  struct Opened {
    std::shared_ptr<Session> session;  // null when the open failed
    std::string error;                 // why it failed
    SessionOptions options;            // what was opened, and how the work baseline follows it
    WorkBaseline baseline = WorkBaseline::kClean;
    std::string what;            // its name in the progress line and the messages
    std::function<void()> then;  // to run once it is in place
    double read_s = 0;           // from start to the frame that took it
  };

  // `wake` is called on the worker when the open finished (the frame loop may be waiting for events).
  explicit SessionLoader(std::function<void()> wake) : wake_(std::move(wake)) {}

  // Starts opening `options` at now_s. Throws InputError(what) while another open is under way.
  void start(const SessionOptions& options, WorkBaseline baseline, const std::string& what, std::function<void()> then,
             double now_s);
  bool pending() const { return pending_; }
  // What is opening (pending() only).
  const std::string& what() const { return request_.what; }
  // The finished open, once; none while it runs or when nothing was started.
  std::optional<Opened> take_finished(double now_s);

 private:
  struct Status {
    enum class Phase { kIdle, kRunning, kDone, kFailed } phase = Phase::kIdle;
    std::shared_ptr<Session> session;
    std::string error;
    bool running() const { return phase == Phase::kRunning; }
  };
  std::function<void()> wake_;
  StatusJob<Status> job_;
  bool pending_ = false;
  Opened request_;  // what was asked, without the result
  double started_s_ = 0;
};

}  // namespace sb::app
