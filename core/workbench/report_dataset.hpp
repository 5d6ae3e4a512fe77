#pragma once
// Whether a residual analysis (a report of `shearbench residual --json`) belongs to what the workbench has open,
// and which dataset a report opens on its own. A report names the dataset it was computed on ("dataset":
// "twin_sphere35"); shown over another dataset or a scene, its corrected model and its residual fields answer a
// question about other data, so it is refused with a status line naming both, never shown silently.
#include <string>

namespace sb {

// The name a report uses for a dataset folder: its last component ("data:twin/twin_sphere35/" -> "twin_sphere35").
// Empty for an empty path.
std::string dataset_name(const std::string& dataset_dir);

struct ReportDatasetCheck {
  bool load = false;    // true: show the report over what is open
  std::string message;  // the status line either way
};

// `report_file` as shown to the user, `report_dataset` the report's "dataset" (empty: an older report naming
// none, loaded with a note), `open_dataset_dir` the open dataset (empty: a scene is open). Pure.
ReportDatasetCheck check_report_dataset(const std::string& report_file, const std::string& report_dataset,
                                        const std::string& open_dataset_dir);

// The dataset `shearbench gui --residual R` opens when no --dataset or --scene is given: "data:twin/<name>" or
// "data:raw/<name>" when that folder of `data_root` holds a dataset.json, else empty (an injected set such as
// "twin_sphere35+lens_distortion" is not on disk: the default scene opens and the report is refused).
std::string report_dataset_path(const std::string& report_dataset, const std::string& data_root);

}  // namespace sb
