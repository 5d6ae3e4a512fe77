#pragma once
// A long task on its own thread whose progress is a Status value the UI copies every frame (MuJoCo
// simulate style: the UI never waits on the work). The task reads the cancel flag between units of work
// and publishes through update(); it must leave a Status whose running() is false when it returns.
// Starting again or destroying the job cancels and joins the running task. Used by FitJob and
// FieldExportJob.
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace sb {

template <class Status>
class StatusJob {
 public:
  using Task = std::function<void(const std::atomic<bool>& cancel, StatusJob& job)>;

  StatusJob() = default;
  StatusJob(const StatusJob&) = delete;
  StatusJob& operator=(const StatusJob&) = delete;
  ~StatusJob() { stop(); }

  // Cancels and joins a running task, publishes `initial` (running), then runs `task` on a new thread.
  void start(Status initial, Task task) {
    stop();
    cancel_ = false;
    update([&](Status& s) { s = std::move(initial); });
    worker_ = std::thread([this, task = std::move(task)] { task(cancel_, *this); });
  }
  void cancel() { cancel_ = true; }
  Status status() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }
  // Blocks until the status is no longer running (tests, headless renders).
  void wait() const {
    while (status().running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  // Edits the published status under the lock (from the task).
  template <class Edit>
  void update(Edit&& edit) {
    std::lock_guard<std::mutex> lock(mutex_);
    edit(status_);
  }

 private:
  void stop() {
    cancel();
    if (worker_.joinable()) worker_.join();
  }
  std::thread worker_;
  std::atomic<bool> cancel_{false};
  mutable std::mutex mutex_;
  Status status_;
};

}  // namespace sb
