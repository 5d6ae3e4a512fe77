#pragma once
// The field export row of the Display section: every model's field along the current path (replay or drags)
// as tsd/1 datasets, one per model, on a worker thread (core/workbench/field_export); while it runs, a
// progress bar and Cancel take the row's place, and once it has ended the status bar says how.
#include <string>

#include "core/workbench/field_export.hpp"
#include "widgets/workbench_request.hpp"

namespace sb::ui {

class ExportRow {
 public:
  void draw(WorkbenchRequest& req);
  void start(FieldExportRequest request);
  FieldExportStatus status() const { return job_.status(); }
  void wait() const { job_.wait(); }
  // Running, or ended and not yet reported (the window keeps redrawing until it is).
  bool busy() const { return job_.status().running() || !reported_; }
  // Once per export, when it has ended: what happened, for the status bar (false while nothing to say).
  bool take_report(std::string& message);

 private:
  std::string folder_ = "fields_export";
  FieldExportJob job_;
  bool reported_ = true;  // the last export's end is in the status bar
};

}  // namespace sb::ui
