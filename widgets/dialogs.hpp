#pragma once
// The workbench's modal dialogs: a question with buttons (the quit and restore questions) and the line
// shown while a session opens on its worker.
#include <chrono>
#include <string>
#include <vector>

#include "widgets/workbench_request.hpp"

namespace sb::ui {

// A modal question with buttons; the choice comes back once in WorkbenchRequest::answer.
class QuestionDialog {
 public:
  void ask(std::string id, std::string text, std::vector<std::string> buttons);
  bool asking() const { return !id_.empty(); }
  void draw(WorkbenchRequest& req);

 private:
  std::string id_, text_;
  std::vector<std::string> buttons_;
};

// While a session opens on its worker: a modal line with the elapsed time and a moving bar; the window keeps
// drawing (the old session plays on behind it) and takes no input until the new one is swapped in.
class LoadingDialog {
 public:
  // What is being opened ("" when done).
  void set(std::string what);
  bool loading() const { return !what_.empty(); }
  void draw();

 private:
  std::string what_;
  std::chrono::steady_clock::time_point since_;
};

}  // namespace sb::ui
