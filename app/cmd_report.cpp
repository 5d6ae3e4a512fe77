// `shearbench report --out docs/fidelity.md [--datasets a,b] [--models m,n] [--analysis notes.md]`:
// fits every model on each dataset's calibration split, scores it on the validation split, and writes
// the fidelity page (core/calibration/report.hpp) atomically.
#include <cstdio>
#include <fstream>
#include <sstream>

#include "app/command.hpp"
#include "core/base/data_root.hpp"
#include "core/calibration/report.hpp"

namespace sb::app {
namespace {

struct ReportArgs {
  std::vector<std::string> datasets = {"data:twin/twin_sphere35", "data:twin/twin_sphere8", "data:twin/twin_torus",
                                       "data:twin/twin_punch"};
  std::vector<std::string> models;
  std::string analysis;
  std::string robust = "none";
  bool no_joint = false;
  std::string out;
};

int run_report(const ReportArgs& a, const GlobalOptions& g) {
  FidelityOptions o;
  o.data_root = resolve_data_root(g.data_root_flag);
  for (const auto& d : a.datasets) o.dataset_dirs.push_back(resolve_path(d, o.data_root, ""));
  o.models = a.models;
  for (const auto& id : o.models) default_params(id);
  o.fit.joint = !a.no_joint;
  o.fit.robust = parse_robust_loss(a.robust);
  o.log = [&](const std::string& line) {
    if (!g.quiet) std::fprintf(stderr, "%s\n", line.c_str());
  };
  std::string analysis;
  if (!a.analysis.empty()) {
    std::ifstream f(a.analysis);
    if (!f) throw InputError(a.analysis, "cannot read the analysis file");
    std::stringstream ss;
    ss << f.rdbuf();
    analysis = ss.str();
  }
  const auto results = run_fidelity(o);
  write_file_atomic(a.out, fidelity_markdown(results, o, analysis));
  if (!g.quiet) std::fprintf(stderr, "report: wrote %s\n", a.out.c_str());
  return 0;
}

void add_flags(CLI::App& sub, ReportArgs& a) {
  sub.add_option("--datasets", a.datasets, "dataset folders (default: the four twin sets)")->delimiter(',');
  sub.add_option("--models", a.models, "model ids (default: all)")->delimiter(',');
  sub.add_option("--analysis", a.analysis, "hand-written Markdown appended after the generated reading");
  sub.add_option("--robust", a.robust, "robust loss of the fits: none | huber | cauchy")
      ->check(CLI::IsMember({"none", "huber", "cauchy"}));
  sub.add_flag("--no-joint", a.no_joint, "skip the joint refinement after the stages");
  sub.add_option("--out", a.out, "Markdown file to write")->required();
}

const Subcommand<ReportArgs> kReportCommand{
    "report", "fit every model on calibration, score on validation, write the fidelity table", 37, add_flags,
    run_report};

}  // namespace
}  // namespace sb::app
