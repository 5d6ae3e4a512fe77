#include "core/workbench/report_dataset.hpp"

#include <filesystem>

namespace sb {

namespace fs = std::filesystem;

std::string dataset_name(const std::string& dataset_dir) {
  std::string p = dataset_dir.rfind("data:", 0) == 0 ? dataset_dir.substr(5) : dataset_dir;
  while (!p.empty() && (p.back() == '/' || p.back() == '\\')) p.pop_back();
  const std::size_t slash = p.find_last_of("/\\");
  return slash == std::string::npos ? p : p.substr(slash + 1);
}

ReportDatasetCheck check_report_dataset(const std::string& report_file, const std::string& report_dataset,
                                        const std::string& open_dataset_dir) {
  const std::string open = dataset_name(open_dataset_dir);
  if (report_dataset.empty())
    return {true, "loaded residual analysis " + report_file + " (it names no dataset: check it is " +
                      (open.empty() ? std::string("this scene's") : open) + ")"};
  if (report_dataset == open) return {true, "loaded residual analysis " + report_file + " of " + open};
  const std::string shown = open.empty() ? std::string("a scene (no dataset)") : "dataset " + open;
  return {false, "not loaded: " + report_file + " is a residual analysis of dataset " + report_dataset + ", the open " +
                     "one is " + shown + "; open " + report_dataset + " first"};
}

std::string report_dataset_path(const std::string& report_dataset, const std::string& data_root) {
  if (report_dataset.empty() || data_root.empty() || report_dataset.find_first_of("/\\") != std::string::npos)
    return "";
  for (const char* group : {"twin", "raw"}) {
    std::error_code ec;
    if (fs::is_regular_file(fs::path(data_root) / group / report_dataset / "dataset.json", ec))
      return std::string("data:") + group + "/" + report_dataset;
  }
  return "";
}

}  // namespace sb
